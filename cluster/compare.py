#!/usr/bin/env python3
"""Compare pmu50 regression folders (standard library only).

compare.py runs A B        the verdict of every seed and the coverage of run A equal run B's
                           (exit 0), or say what differs (exit 1)
compare.py complete SHARD  every seed of SHARD has a result line (exit 0), or not (exit 1)
compare.py missing SHARD MISSING_TXT
                           the seeds listed in MISSING_TXT are exactly SHARD's seeds that
                           have no result line (exit 0), or say which differ (exit 1)
"""

import json
import os
import sys

# A result line's fields that say how and where a seed ran, not what it did.
CIRCUMSTANCES = {"wall_ms", "where"}


def results(folder):
    path = os.path.join(folder, "results.jsonl")
    out = {}
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            if not line.strip():
                continue
            rec = json.loads(line)
            seed = rec["seed"]
            if seed in out:
                sys.exit(f"{path}:{n}: seed {seed} given twice")
            out[seed] = rec
    return out


def outcome(rec):
    return {k: v for k, v in rec.items() if k not in CIRCUMSTANCES}


def runs(a, b):
    ra, rb = results(a), results(b)
    ok = True
    only_a, only_b = sorted(set(ra) - set(rb)), sorted(set(rb) - set(ra))
    if only_a or only_b:
        ok = False
        print(
            f"  seeds: {len(only_a)} only in {a} (first {only_a[:5]}), "
            f"{len(only_b)} only in {b} (first {only_b[:5]})"
        )
    diff = [s for s in sorted(set(ra) & set(rb)) if outcome(ra[s]) != outcome(rb[s])]
    verdicts = {}
    for rec in ra.values():
        verdicts[rec["verdict"]] = verdicts.get(rec["verdict"], 0) + 1
    tally = ", ".join(f"{n} {v}" for v, n in sorted(verdicts.items()))
    if diff:
        ok = False
        s = diff[0]
        print(
            f"  verdicts: {len(diff)} seeds differ, "
            f"first {s}: {outcome(ra[s])} against {outcome(rb[s])}"
        )
    else:
        print(f"  verdicts:    identical, {len(ra)} seeds ({tally})")
    ca = open(os.path.join(a, "coverage.json"), "rb").read()
    cb = open(os.path.join(b, "coverage.json"), "rb").read()
    if ca == cb:
        print(f"  coverage:    identical (coverage.json byte for byte, {len(ca)} bytes)")
    else:
        ok = False
        ja, jb = json.loads(ca), json.loads(cb)
        keys = (
            sorted(k for k in set(ja) | set(jb) if ja.get(k) != jb.get(k))
            if isinstance(ja, dict) and isinstance(jb, dict)
            else ["(top level)"]
        )
        print(f"  coverage:    DIFFERENT, fields {keys[:10]}")
    wa = sum(r.get("wall_ms", 0) for r in ra.values())
    wb = sum(r.get("wall_ms", 0) for r in rb.values())
    hosts = sorted({(r.get("where") or {}).get("host", "?") for r in ra.values()})
    shards = sorted({(r.get("where") or {}).get("shard") for r in ra.values()}, key=str)
    print(
        f"  seeds' wall_ms summed: {wa / 1000:.2f} s in {len(shards)} shards on "
        f"{', '.join(map(str, hosts))}; {wb / 1000:.2f} s in one process"
    )
    print(
        "  => "
        + (
            "the merged run equals the one-process run"
            if ok
            else "the merged run DIFFERS from the one-process run"
        )
    )
    return 0 if ok else 1


def missing(shard, listing):
    with open(os.path.join(shard, "regress.json"), encoding="utf-8") as f:
        run = json.load(f)
    seeds = set(shard_seeds(run))
    done = set(results(shard))
    with open(listing, encoding="utf-8") as f:
        listed = {int(tok) for line in f for tok in line.replace(",", " ").split()}
    want = seeds - done
    if listed == want:
        print(
            f"  missing:     exactly the cancelled shard's {len(want)} unfinished seeds "
            f"({len(done)} of its {len(seeds)} finished)"
        )
        return 0
    print(
        f"  missing:     listed {len(listed)}, expected {len(want)}; "
        f"listed not expected {sorted(listed - want)[:10]}, "
        f"expected not listed {sorted(want - listed)[:10]}"
    )
    return 1


def shard_seeds(run):
    """The seeds of one shard, as regress.json states them."""
    start, n = run["start_seed"], run["iterations"]
    shard = run.get("shard")
    if not shard:
        return range(start, start + n)
    i, k = shard["index"], shard["count"]
    # Part i of k: [start + i*n/k, start + (i+1)*n/k) (docs/cluster.md, Shards).
    return range(start + i * n // k, start + (i + 1) * n // k)


def complete(shard):
    """Every seed of the folder's run (or shard) has a result line."""
    with open(os.path.join(shard, "regress.json"), encoding="utf-8") as f:
        run = json.load(f)
    return 0 if set(shard_seeds(run)) <= set(results(shard)) else 1


def main(argv):
    if len(argv) == 3 and argv[1] == "complete":
        return complete(argv[2])
    if len(argv) == 4 and argv[1] == "runs":
        return runs(argv[2], argv[3])
    if len(argv) == 4 and argv[1] == "missing":
        return missing(argv[2], argv[3])
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
