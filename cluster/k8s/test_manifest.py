#!/usr/bin/env python3
"""The Indexed Job manifest's index handling, without a Kubernetes cluster.

Reads cluster/k8s/pmu50-regress-job.yaml, checks that it is an Indexed Job whose JOB_COMPLETIONS
equals spec.completions, then runs its container command the way Kubernetes would, once per
index with JOB_COMPLETION_INDEX set, for a small run (3 indices, 30 seeds, pmu50 from PMU50_BIN
on PATH, /results replaced by a temporary folder). The shards merged must equal the
one-process run of the same seeds, and every result line must name its index.
A pod run again for an index (after a failure) resumes that index's folder, and an index past
the last one must be refused (exit 2).

  PYTHONPATH=cluster python3 cluster/k8s/test_manifest.py [PMU50_BIN]     exit 0 pass, 1 fail
"""

import os
import re
import shutil
import subprocess
import sys
import tempfile

import compare  # cluster/compare.py (PYTHONPATH=cluster)

HERE = os.path.dirname(os.path.abspath(__file__))
MANIFEST = os.path.join(HERE, "pmu50-regress-job.yaml")


def fail(msg):
    print(f"test_manifest: FAIL: {msg}")
    sys.exit(1)


def parse(text):
    """The few fields the test needs, read from the manifest's own layout (standard library
    only; cross-checked with PyYAML when it is installed)."""
    lines = text.splitlines()
    spec = {}
    for key in ("completionMode", "completions", "parallelism"):
        m = re.search(rf"^\s+{key}:\s*(\S+)\s*$", text, re.M)
        spec[key] = m.group(1) if m else None
    env = {}
    command = []
    i = 0
    while i < len(lines):
        line = lines[i]
        stripped = line.strip()
        if stripped == "env:":
            ind = len(line) - len(line.lstrip())
            i += 1
            name = None
            while i < len(lines) and (
                not lines[i].strip() or len(lines[i]) - len(lines[i].lstrip()) > ind
            ):
                s = lines[i].strip()
                if s.startswith("- name:"):
                    name = s.split(":", 1)[1].strip()
                elif s.startswith("value:") and name:
                    env[name] = s.split(":", 1)[1].strip().strip('"')
                i += 1
            continue
        if stripped == "command:":
            ind = len(line) - len(line.lstrip())
            i += 1
            while (
                i < len(lines)
                and lines[i].strip().startswith("- ")
                and len(lines[i]) - len(lines[i].lstrip()) > ind
            ):
                item_ind = len(lines[i]) - len(lines[i].lstrip())
                item = lines[i].strip()[2:].strip()
                i += 1
                if item in (">-", ">"):
                    parts = []
                    while i < len(lines) and len(lines[i]) - len(lines[i].lstrip()) > item_ind + 1:
                        parts.append(lines[i].strip())
                        i += 1
                    item = " ".join(parts)
                command.append(item)
            continue
        i += 1
    return spec, env, command


def crosscheck(text, spec, env, command):
    try:
        import yaml
    except ImportError:
        return "PyYAML not installed: layout parse only"
    doc = yaml.safe_load(text)
    c = doc["spec"]["template"]["spec"]["containers"][0]
    yenv = {e["name"]: e["value"] for e in c["env"] if "value" in e}
    if (
        c["command"] != command
        or yenv != env
        or str(doc["spec"]["completions"]) != spec["completions"]
    ):
        fail(
            f"the layout parse disagrees with PyYAML: {command} {env} against {c['command']} {yenv}"
        )
    return "PyYAML agrees"


def main():
    binary = os.path.abspath(
        sys.argv[1]
        if len(sys.argv) > 1
        else os.path.join(HERE, "..", "..", "target", "release", "pmu50")
    )
    if not os.access(binary, os.X_OK):
        fail(f"no pmu50 binary at {binary}")
    text = open(MANIFEST, encoding="utf-8").read()
    spec, env, command = parse(text)
    how = crosscheck(text, spec, env, command)
    if spec["completionMode"] != "Indexed":
        fail(f"completionMode is {spec['completionMode']}, not Indexed")
    if env.get("JOB_COMPLETIONS") != spec["completions"]:
        fail(
            f"env JOB_COMPLETIONS={env.get('JOB_COMPLETIONS')} but "
            f"spec.completions={spec['completions']}: shards would be lost or run twice"
        )
    if not command or "pmu50" not in " ".join(command):
        fail(f"no pmu50 command found in the manifest: {command}")

    shards, seeds = 3, 30
    tmp = tempfile.mkdtemp(prefix="pmu50-k8s.")
    try:
        bindir = os.path.join(tmp, "bin")
        os.mkdir(bindir)
        os.symlink(binary, os.path.join(bindir, "pmu50"))
        results = os.path.join(tmp, "results")
        os.mkdir(results)
        base = {
            k: v for k, v in os.environ.items() if not k.startswith(("SLURM_", "JOB_COMPLETION"))
        }
        base.update(env)
        base.update(
            PATH=bindir + os.pathsep + base.get("PATH", ""),
            JOB_COMPLETIONS=str(shards),
            PMU50_SEEDS=str(seeds),
            PMU50_OUT=results,
        )
        for index in range(shards):
            run = subprocess.run(
                command,
                env=dict(base, JOB_COMPLETION_INDEX=str(index)),
                capture_output=True,
                text=True,
            )
            if run.returncode not in (0, 1):
                fail(f"index {index}: exit {run.returncode}: {run.stderr.strip()}")
            for seed, rec in compare.results(os.path.join(results, f"shard-{index}")).items():
                where = rec.get("where") or {}
                if (
                    where.get("k8s_index") != str(index)
                    or where.get("shard") != f"{index}/{shards}"
                ):
                    fail(f"index {index}: seed {seed}'s line says where={where}")
        # A pod replacing a failed one for index 1: its folder has a shard of 4 seeds cut short.
        retry = os.path.join(results, "shard-1", "results.jsonl")
        kept = open(retry, encoding="utf-8").readlines()
        with open(retry, "w", encoding="utf-8") as f:
            f.writelines(kept[:4])
        again = subprocess.run(
            command, env=dict(base, JOB_COMPLETION_INDEX="1"), capture_output=True, text=True
        )
        lines = len(open(retry, encoding="utf-8").readlines())
        if again.returncode not in (0, 1) or lines != len(kept):
            fail(
                f"index 1 run again after a failure: exit {again.returncode}, {lines} result "
                f"lines, expected {len(kept)}: {again.stderr.strip()}"
            )
        past = subprocess.run(
            command,
            env=dict(base, JOB_COMPLETION_INDEX=str(shards)),
            capture_output=True,
            text=True,
        )
        if past.returncode != 2:
            fail(
                f"index {shards} of {shards} shards: exit {past.returncode}, expected 2 (bad input)"
            )
        merged, one = os.path.join(tmp, "merged"), os.path.join(tmp, "one")
        shard_dirs = [os.path.join(results, f"shard-{i}") for i in range(shards)]
        m = subprocess.run(
            [binary, "merge", "--out", merged] + shard_dirs[::-1], capture_output=True, text=True
        )
        if m.returncode not in (0, 1):
            fail(f"merge: exit {m.returncode}: {m.stderr.strip()}")
        o = subprocess.run(
            [
                binary,
                "regress",
                "--start-seed",
                env.get("PMU50_START_SEED", "1"),
                "--iterations",
                str(seeds),
                "--out",
                one,
            ],
            capture_output=True,
            text=True,
        )
        if o.returncode not in (0, 1):
            fail(f"one-process run: exit {o.returncode}: {o.stderr.strip()}")
        if compare.runs(merged, one) != 0:
            fail("the merged shards differ from the one-process run")
        print(
            "test_manifest: ok: Indexed Job, JOB_COMPLETIONS = completions = "
            f"{spec['completions']} ({how}); its command run for JOB_COMPLETION_INDEX "
            f"0..{shards - 1} of {shards}, merged = one process; "
            f"index 1 again resumes its folder; index {shards} refused"
        )
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
