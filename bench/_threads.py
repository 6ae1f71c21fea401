import asyncio, sys, time, os, random
sys.path.insert(0, "bench")
from bench_app_load import Tab, start_server, CLK_TCK, explore
def threads(pid):
    out = {}
    for tid in os.listdir(f"/proc/{pid}/task"):
        try:
            s = open(f"/proc/{pid}/task/{tid}/stat").read()
        except FileNotFoundError:
            continue
        name = s[s.index("(")+1:s.rindex(")")]
        f = s.rsplit(")", 1)[1].split()
        out[tid] = (name, (int(f[11]) + int(f[12])) / CLK_TCK)
    return out
async def main(n, seconds):
    proc, port = start_server("panda", False)
    tabs = [Tab() for _ in range(n)]
    for t in tabs:
        await t.connect(f"ws://127.0.0.1:{port}"); await asyncio.wait_for(t.drawn.wait(), 120)
    await asyncio.sleep(2)
    a = threads(proc.pid)
    rng = random.Random(1)
    await asyncio.gather(*(explore(t, time.perf_counter() + seconds, rng) for t in tabs))
    b = threads(proc.pid)
    rows = sorted(((b[t][1] - a.get(t, (0, 0))[1], b[t][0], t) for t in b), reverse=True)
    changes = sum(getattr(t, "sent", 0) for t in tabs)
    print("changes", changes, "total cpu s", round(sum(r[0] for r in rows), 2))
    for r in rows[:6]: print(f"  {r[0]:.2f} s  {r[1]} {r[2]}")
    proc.terminate(); proc.wait(15)
asyncio.run(main(int(sys.argv[1]), float(sys.argv[2])))
