"""The robot-file writer (robots.dumps) is the reader's exact inverse: read → write → read gives the
same robot, configurations, motions, symbols, task and planar flag, for every library robot and for
random tables; hostile names are escaped so they come back unchanged and cannot add keys or tables."""

from __future__ import annotations

import dataclasses
import math
import sys

import numpy as np
import pytest

import robots
from kinematics import NamedConfiguration, Robot, fk, jacobian
from kinematics.errors import RobotDefinitionError
from robots import files

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def assert_same_file(a: files.RobotFile, b: files.RobotFile) -> None:
    """Every fact a robot file holds, compared exactly (floats bit for bit)."""
    ra, rb = a.robot, b.robot
    for attr in ("name", "title", "description", "source", "convention", "planar", "task"):
        assert getattr(ra, attr) == getattr(rb, attr), attr
    assert ra.dh == rb.dh  # DHRow is a dataclass of floats: == is bit-exact
    assert [(j.name, j.kind, j.qlim) for j in ra.joints] == [(j.name, j.kind, j.qlim) for j in rb.joints]
    assert np.array_equal(ra.base, rb.base) and np.array_equal(ra.tool, rb.tool)
    assert dict(ra.param_names) == dict(rb.param_names)
    assert _texts(ra.translations) == _texts(rb.translations)
    assert len(ra.configurations) == len(rb.configurations)
    for ca, cb in zip(ra.configurations, rb.configurations, strict=True):
        assert (ca.name, ca.description, ca.singular) == (cb.name, cb.description, cb.singular)
        assert np.array_equal(ca.q, cb.q), ca.name
        assert _texts(ca.translations) == _texts(cb.translations), ca.name
    assert len(a.motions) == len(b.motions)
    for ma, mb in zip(a.motions, b.motions, strict=True):
        assert (ma.name, ma.description, ma.frame, ma.speed, ma.start) == (
            mb.name,
            mb.description,
            mb.frame,
            mb.speed,
            mb.start,
        )
        assert np.array_equal(ma.q, mb.q) and np.array_equal(ma.twist, mb.twist)
        assert (ma.rates is None) == (mb.rates is None)
        assert ma.rates is None or np.array_equal(ma.rates, mb.rates)
        assert _texts(ma.translations) == _texts(mb.translations), ma.name
    assert ra.fingerprint() == rb.fingerprint()


def _texts(translations):
    """Translations as plain dicts (language → {key: text}), to compare."""
    return {code: dict(texts) for code, texts in translations.items()}


@pytest.mark.parametrize("name", robots.names())
def test_every_library_robot_survives_read_write_read(name):
    first = files.read(robots.DATA_DIR / f"{name}.toml")
    text = robots.dumps(first.robot, first.motions)
    again = robots.loads(text, f"{name}.toml")
    assert_same_file(first, again)
    assert robots.dumps(again.robot, again.motions) == text  # writing is a fixed point
    # The facts the old writer dropped are in the text, as the reader sees them.
    doc = tomllib.loads(text)
    source = tomllib.loads((robots.DATA_DIR / f"{name}.toml").read_text(encoding="utf-8"))
    assert doc["planar"] == source.get("planar", False)
    assert doc["task"] == source.get("task", "auto")
    assert doc.get("symbols", {}) == source.get("symbols", {})
    # Translated texts: every language and key the file gives comes back (one paragraph each).
    folded = {
        c: {k: " ".join(v.split()) for k, v in t.items()} for c, t in source.get("translations", {}).items()
    }
    assert doc.get("translations", {}) == folded
    for out, given in zip(doc.get("configurations", []), source.get("configurations", []), strict=True):
        assert out.get("translations", {}) == given.get("translations", {}), given["name"]
    for out, given in zip(doc.get("motions", []), source.get("motions", []), strict=True):
        assert out.get("translations", {}) == given.get("translations", {}), given["name"]
    assert [m["name"] for m in doc.get("motions", [])] == [m["name"] for m in source.get("motions", [])]
    assert [m["start"] for m in doc.get("motions", [])] == [m["start"] for m in source.get("motions", [])]
    # Degrees are written as the shortest decimals naming the same radians as the file's own.
    for row_out, row_in in zip(doc["joints"], source["joints"], strict=True):
        for key in ("alpha", "theta"):
            assert math.radians(row_out[key]) == math.radians(row_in[key])
            assert len(repr(float(row_out[key]))) <= len(repr(float(row_in[key])))
        if row_in["joint"] == "revolute" and "qlim" in row_in:
            assert [math.radians(v) for v in row_out["qlim"]] == [math.radians(v) for v in row_in["qlim"]]


def _random_robot(rng: np.random.Generator, convention: str, from_degrees: bool) -> Robot:
    """A random DH robot; its angles are radians of 3-decimal degrees, or any radians."""

    def angle(lo: float = -180.0, hi: float = 180.0) -> float:
        deg = float(rng.uniform(lo, hi))
        return math.radians(round(deg, 3)) if from_degrees else math.radians(deg)

    n = int(rng.integers(1, 7))
    rows = []
    for i in range(n):
        kind = "prismatic" if rng.random() < 0.3 else "revolute"
        qlim = (
            (angle(-180, -1), angle(1, 180))
            if kind == "revolute"
            else (-float(rng.random()), float(rng.random()))
        )
        row = {
            "joint": kind,
            "a": float(rng.uniform(-1, 1)),
            "alpha": angle(),
            "d": float(rng.uniform(-1, 1)),
        }
        row |= {"theta": angle(), "qlim": qlim, "name": f"j{i}" if rng.random() < 0.5 else ""}
        rows.append(row)
    confs = [NamedConfiguration(f"c{k}", np.array([angle() for _ in range(n)])) for k in range(2)]
    base = np.eye(4)
    base[:3, 3] = rng.uniform(-1, 1, 3)
    return Robot.from_dh(rows, convention, base=base, name="random", configurations=confs)


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_random_tables_in_degrees_come_back_bit_for_bit(convention):
    rng = np.random.default_rng(16)
    for _ in range(40):
        robot = _random_robot(rng, convention, from_degrees=True)
        once = files.RobotFile(robot)
        assert_same_file(once, robots.loads(robots.dumps(robot), "random.toml"))


def test_any_radians_come_back_within_one_ulp_and_the_jacobian_with_them():
    rng = np.random.default_rng(61)
    for _ in range(40):
        robot = _random_robot(rng, "standard", from_degrees=False)
        back = robots.loads(robots.dumps(robot), "random.toml").robot
        for ra, rb in zip(robot.dh, back.dh, strict=True):
            for x, y in ((ra.alpha, rb.alpha), (ra.theta, rb.theta)):
                assert abs(x - y) <= math.ulp(x), (x, y)
        q = rng.uniform(-1, 1, robot.dof)
        np.testing.assert_allclose(jacobian(back, q), jacobian(robot, q), rtol=0, atol=1e-13)
        np.testing.assert_allclose(fk(back, q), fk(robot, q), rtol=0, atol=1e-13)


HOSTILE = [
    'q1 "quoted"',
    'end"\nname = "injected"\n[[joints]]',
    "back\\slash \\u0041 \\",
    "tab\there\r\n\f\b",
    "nul\x00 del\x7f esc\x1b",
    "]] [tool] xyz = [1, 2, 3] # not a comment",
    "'single' '''triple''' \"\"\"",
    "unicode ωθ ∂ 漢字 \u2028 \U0001f916",
]


def test_hostile_names_are_escaped_and_come_back_unchanged():
    rows = [
        {"joint": "revolute", "a": 1.0, "alpha": 0.0, "d": 0.0, "theta": 0.0, "name": name}
        for name in HOSTILE
    ]
    n = len(rows)
    confs = [NamedConfiguration(name, np.zeros(n), description=name, singular=name) for name in HOSTILE]
    robot = Robot.from_dh(rows, name="hostile", title=HOSTILE[1], source=HOSTILE[5], configurations=confs)
    motion = files.MotionPreset(
        HOSTILE[2], HOSTILE[3], np.zeros(n), np.arange(6.0), "tool", 0.5, None, HOSTILE[0]
    )
    text = robots.dumps(robot, [motion], header=["a header\nwith = 'a line break'"])
    doc = tomllib.loads(text)  # valid TOML, with exactly the keys and tables the writer meant
    assert set(doc) == {
        "name",
        "title",
        "description",
        "source",
        "convention",
        "planar",
        "task",
        "joints",
        "configurations",
        "motions",
    }
    assert len(doc["joints"]) == n and len(doc["configurations"]) == n and len(doc["motions"]) == 1
    assert [j["name"] for j in doc["joints"]] == HOSTILE
    assert [c["name"] for c in doc["configurations"]] == HOSTILE
    assert doc["motions"][0]["start"] == HOSTILE[0] and doc["motions"][0]["name"] == HOSTILE[2]
    back = robots.loads(text, "hostile.toml")
    assert [j.name for j in back.robot.joints] == HOSTILE
    assert [c.name for c in back.robot.configurations] == HOSTILE
    assert [c.singular for c in back.robot.configurations] == HOSTILE
    # Texts are one paragraph (the reader folds white space), so they come back folded.
    assert back.robot.title == " ".join(HOSTILE[1].split())
    assert [c.description for c in back.robot.configurations] == [" ".join(h.split()) for h in HOSTILE]
    assert (back.motions[0].name, back.motions[0].start) == (HOSTILE[2], HOSTILE[0])


def test_a_hostile_file_stem_is_escaped_too():
    robot = robots.load("planar2")
    stem = 'x" = 1\n[base]\nxyz = [9, 9, 9]\n#'
    doc = tomllib.loads(robots.dumps(robot, name=stem))
    assert doc["name"] == stem and "base" not in doc


def test_what_cannot_be_written_is_refused_with_a_reason():
    with pytest.raises(RobotDefinitionError, match="lone surrogate"):
        robots.dumps(
            Robot.from_dh([{"joint": "revolute", "a": 1, "alpha": 0, "d": 0, "theta": 0}], name="a\ud800")
        )
    chain = robots.load("planar2")
    urdf_like = Robot(chain.name, chain.joints, chain.axes)
    with pytest.raises(RobotDefinitionError, match="no DH table"):
        robots.dumps(urdf_like)
    stray = files.MotionPreset("stray", "", np.array([0.1, 0.2]), np.zeros(6), "base")
    with pytest.raises(RobotDefinitionError, match="'stray': its start is not a named configuration"):
        robots.dumps(chain, [stray])
    found = files.MotionPreset("found", "", chain.configurations[0].q.copy(), np.zeros(6), "base")
    assert tomllib.loads(robots.dumps(chain, [found]))["motions"][0]["start"] == chain.configurations[0].name


def test_translated_texts_come_back_and_hostile_ones_stay_texts():
    """Translations (the title and description per language, a configuration's and a motion's
    description) survive read → write → read, escaped like every other text: a translation holding
    quotes, a line break and a table header stays one string of its language."""
    evil = 'Człon "2"\n[translations.pt]\ntitle = "x"\n#'
    rows = [{"joint": "revolute", "a": 1.0, "alpha": 0.0, "d": 0.0, "theta": 0.0}] * 2
    conf = NamedConfiguration("home", np.zeros(2), "Home.", translations={"pl": {"description": evil}})
    robot = Robot.from_dh(
        rows,
        name="tr",
        title="Two links",
        configurations=[conf],
        translations={"pl": {"title": evil}, "es": {"description": "Dos eslabones."}},
    )
    motion = files.MotionPreset(
        "m", "Moves.", np.zeros(2), np.zeros(6), "base", translations={"pt": {"description": "Move."}}
    )
    text = robots.dumps(robot, [motion])
    doc = tomllib.loads(text)
    assert set(doc["translations"]) == {"pl", "es"}  # no "pt" table smuggled in by the evil text
    back = robots.loads(text, "tr.toml")
    folded = " ".join(evil.split())
    assert _texts(back.robot.translations) == {
        "pl": {"title": folded},
        "es": {"description": "Dos eslabones."},
    }
    assert _texts(back.robot.configurations[0].translations) == {"pl": {"description": folded}}
    assert _texts(back.motions[0].translations) == {"pt": {"description": "Move."}}
    assert robots.dumps(back.robot, back.motions) == robots.dumps(
        robots.loads(robots.dumps(back.robot, back.motions), "tr.toml").robot, back.motions
    )


def test_a_file_with_english_only_reads_with_no_translations():
    chain = robots.load("planar2")
    plain = Robot.from_dh(
        [{"joint": r.joint, "a": r.a, "alpha": r.alpha, "d": r.d, "theta": r.theta} for r in chain.dh],
        name="plain",
        title="Plain",
    )
    text = robots.dumps(plain)
    assert "translations" not in text
    assert dict(robots.loads(text, "plain.toml").robot.translations) == {}


def _english_only(name: str) -> Robot:
    """Library robot ``name`` with its translations dropped (a file as a user might write it)."""
    robot = robots.load(name)
    confs = tuple(dataclasses.replace(c, translations={}) for c in robot.configurations)
    return dataclasses.replace(robot, translations={}, configurations=confs)


@pytest.mark.parametrize(
    ("snippet", "message"),
    [
        (
            '[translations.fr]\ntitle = "Bras"\n',
            "translations' \\(a language\\): expected one of pt, es, pl; got 'fr'",
        ),
        ('[translations.pl]\nsource = "x"\n', "translations.pl: unknown key.*'source'"),
        ("[translations.pl]\ntitle = 3\n", "translations.pl, key 'title': expected a str"),
        ("[translations]\npl = 'Robot'\n", "translations.pl: expected a table"),
    ],
)
def test_a_wrong_translation_is_refused_in_words(snippet, message):
    text = robots.dumps(_english_only("scara"), name="p")
    head, _, rest = text.partition("[[joints]]")
    with pytest.raises(RobotDefinitionError, match=message):
        robots.loads(head + snippet + "\n[[joints]]" + rest, "p.toml")


def test_a_wrong_configuration_translation_is_refused_in_words():
    text = robots.dumps(_english_only("scara"), name="p")
    bad = text.replace('singular = ""', 'singular = ""\ntranslations.pl.name = "dom"', 1)
    with pytest.raises(RobotDefinitionError, match="configurations entry 1, translations.pl: unknown key"):
        robots.loads(bad, "p.toml")
