import asyncio, sys, time, os
sys.path.insert(0, "bench")
from bench_app_load import Tab, start_server, CLK_TCK
def cpu(pid):
    f = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(f[11]) + int(f[12])) / CLK_TCK
async def main(n):
    proc, port = start_server("panda", False)
    tabs = [Tab() for _ in range(n)]
    for t in tabs:
        await t.connect(f"ws://127.0.0.1:{port}"); await asyncio.wait_for(t.drawn.wait(), 120)
    await asyncio.sleep(3)
    c0 = cpu(proc.pid); await asyncio.sleep(5); c1 = cpu(proc.pid)
    print(n, "idle tabs: server CPU %", round((c1 - c0) / 5 * 100, 1))
    proc.terminate(); proc.wait(15)
asyncio.run(main(int(sys.argv[1])))
