"""An uploaded .urdf with xacro left in it (pybullet's husky.urdf holds ``$(optenv …)``) is refused saying
it is unexpanded xacro and what to do, in the tab's language (the catalogs), the piece of xacro and the
file names written as they are (no decimal comma put into ``0.1``); before, the parser's words alone
("expected 3 numbers, found 5"), in English."""

from __future__ import annotations

import pytest
from xacro_helpers import hand_written

from app.core.i18n import translations
from app.services.catalog import RobotCatalog
from app.tab.notices import Notices
from app.tab.robots import TabCatalog
from kinematics.errors import UrdfError


class Client:
    client_id = 7

    def __init__(self) -> None:
        self.shown: list[tuple[str, str]] = []

    def add_notification(self, title: str, body: str, **_: object) -> None:
        self.shown.append((title, body))


LEFT = hand_written().replace('<origin xyz="0.45 0 0"/>', '<origin xyz="$(optenv ARM_X 0.1) 0 0"/>')


@pytest.mark.parametrize(
    ("code", "words"),
    [
        ("en", "husky.urdf is unexpanded xacro (it holds $(optenv ARM_X 0.1)). Expand it first (xacro "
         "husky.urdf.xacro > husky.urdf) and upload the .urdf, or start the lab with --urdf husky.urdf.xacro."),
        ("pl", "husky.urdf to nierozwinięty xacro (zawiera $(optenv ARM_X 0.1)). Najpierw go rozwiń (xacro "
         "husky.urdf.xacro > husky.urdf) i wgraj plik .urdf albo uruchom laboratorium z opcją --urdf "
         "husky.urdf.xacro."),
        ("pt", "husky.urdf é xacro não expandido (contém $(optenv ARM_X 0.1)). Expanda-o antes"),
        ("es", "husky.urdf es xacro sin expandir (contiene $(optenv ARM_X 0.1)). Expandilo antes"),
    ],
)  # fmt: skip
def test_an_uploaded_urdf_with_xacro_left_is_refused_in_the_tab_s_language(code, words):
    tab = TabCatalog(RobotCatalog())
    with pytest.raises(UrdfError) as err:
        tab.add_upload("husky.urdf", LEFT.encode())
    client = Client()
    notices = Notices(client, lambda: False)
    notices.tr = translations(code)
    notices.error(err.value)
    title, body = client.shown[0]
    assert title == translations(code).gettext("That did not work")
    assert body.startswith(f"UrdfError: {words}")
    assert len(body) < 300  # whole: a notice shows 300 characters at most


def test_a_well_formed_upload_still_opens_and_other_refusals_keep_their_words():
    tab = TabCatalog(RobotCatalog())
    assert tab.add_upload("arm.urdf", hand_written().encode()).startswith("kuka_kr6")
    with pytest.raises(UrdfError, match=r"upload 'bad.urdf': .*xyz"):
        tab.add_upload("bad.urdf", hand_written().replace('xyz="0.45 0 0"', 'xyz="0.45 0"').encode())
