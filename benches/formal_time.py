#!/usr/bin/env python3
"""`make bench`, last part: the formal kit's wall time, cold, against its goal and its peer.

Runs, one after the other, with the result cache off (FORMAL_CACHE=0: every property decided
again; the AIGER models are rebuilt too):

  make formal          both parameter sets, the engines' portfolio (ABC scorr and pdr, rIC3)
  make formal-quick    the small set
  ABC alone            hdl/formal/run.py --engines abc, both sets: the kit without rIC3, the
                       engine the kit first had (the peer of the portfolio)

and prints one table: wall time, CPU time of every child process (user + system), the verdict
line of each run, and the goal (60 s and 30 s wall, docs/performance.md). The tools are built
first (make formal-tools), untimed. Exit 1 when a run fails.
"""

import os
import resource
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VPY = os.path.join(ROOT, "target", "venv", "bin", "python")


def timed(cmd, env):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    p = subprocess.run(
        cmd, cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
    )
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    verdict = next((ln for ln in reversed(p.stdout.splitlines()) if ln.startswith("formal:")), "")
    return p.returncode, wall, cpu, verdict, p.stdout


def main():
    env = dict(os.environ, FORMAL_CACHE="0")
    prep = subprocess.run(["make", "-s", "formal-tools", "target/venv/.formal"], cwd=ROOT)
    if prep.returncode != 0:
        print("formal_time: make formal-tools failed", file=sys.stderr)
        return 2
    load = os.getloadavg()[0]
    runs = [
        ("make formal (portfolio, sets default + small)", ["make", "-s", "formal"], 60),
        ("make formal-quick (portfolio, set small)", ["make", "-s", "formal-quick"], 30),
        (
            "ABC alone (run.py --engines abc, both sets)",
            [VPY, "hdl/formal/run.py", "--engines", "abc"],
            None,
        ),
    ]
    rows, failed = [], False
    for name, cmd, goal in runs:
        rc, wall, cpu, verdict, out = timed(cmd, env)
        if rc != 0:
            failed = True
            sys.stdout.write(out[-2000:])
        rows.append((name, wall, cpu, goal, rc, verdict))
    print(
        "\nformal kit, cold (FORMAL_CACHE=0), one run after the other; "
        f"machine: {os.cpu_count()} CPUs, "
        f"load average {load:.2f} at the start\n"
    )
    print(f"| {'run':<48} | {'wall s':>7} | {'CPU s':>7} | {'goal':>6} | verdict")
    print(f"|{'-' * 50}|{'-' * 9}|{'-' * 9}|{'-' * 8}|---")
    for name, wall, cpu, goal, rc, verdict in rows:
        g = f"{goal} s" if goal else "peer"
        mark = "" if rc == 0 else f" (exit {rc})"
        verdict = verdict.removeprefix("formal: ")
        print(f"| {name:<48} | {wall:7.1f} | {cpu:7.1f} | {g:>6} | {verdict}{mark}")
    full, abc = rows[0], rows[2]
    met = "met" if full[1] <= 60 else "MISSED"
    print(
        f"\nmake formal: {full[1]:.1f} s wall against its 60 s goal ({met}); "
        f"ABC alone {abc[1]:.1f} s, {abc[1] / max(full[1], 1e-9):.2f}x the portfolio's wall time"
    )
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
