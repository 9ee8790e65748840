"""The coverage monitor (hdl/formal/pmu50_cov.sv) bound to any RTL with the contract ports.

The monitor reads the twin's ports and some internals (registers, the model's internals, next-state
nets: the table's `signals`). On another RTL each internal input is bound, in this order:

1. `map`: the RTL's own signal that its map (`pmu50 regress --map`, docs/hdl-guide.md "The map")
   names for it, as a hierarchical reference below the DUT (slang resolves it, fields of packed
   structs and elements of arrays included);
2. `ports`: rebuilt from the contract ports as docs/spec.md defines it (pmu50_port_view.sv: the
   key's synchronizer, the parameter registers as the bus wrote them, the timer, the sample), or
   a next-state net read as the port it becomes one edge later. The monitor then runs one cycle
   behind the DUT (every other input through a flop), so that the next state is there;
3. none: an internal that no port shows (the FIG. 17 and FIG. 18 paths): a bin whose classifier
   reads it cannot be decided without the map entry, and is reported undecided with the entry
   it needs.

Which bins read which input is computed from the monitor's text (`dependencies`): the cone of
each `hit_<bin>` wire.
"""

import os
import re

import tomllib

from .common import FORMAL, SetupError

MONITOR = os.path.join(FORMAL, "pmu50_cov.sv")
PORT_VIEW = os.path.join(FORMAL, "pmu50_port_view.sv")

# internals rebuilt from the ports (outputs of pmu50_port_view of the same name)
FROM_VIEW = {
    "sync",
    "tmr",
    "adaptive",
    "pw",
    "pi",
    "ps",
    "si_max",
    "si_min",
    "t1",
    "t2",
    "cth",
    "smp_on",
    "kon",
    "koff",
    "upd",
    "first",
    "chg_s",
    "chg_c",
    "skip_clr",
    "vld",
    "param_wr",
    "c_legal",
    "c_adaptive",
    "c_pw",
    "c_pi",
    "c_ps",
    "c_si_max",
    "c_si_min",
    "c_t1",
    "c_t2",
    "c_cth",
    "c_smp_on",
}
# next-state nets: the port (or expression of ports) they equal one edge later
FROM_NEXT = {
    "si_n": "si",
    "cnt_r_n": "cnt_r",
    "cnt_s_n": "cnt_s",
    "cnt_c_n": "cnt_c",
    "skip_n": "quadrant_skip",
    # |cnt_s - cnt_c| < 2 at CNT_W bits (docs/spec.md 2.7)
    "in_range_n": "((cnt_s - cnt_c) == {CNT_W{1'b0}}"
    " || (cnt_s - cnt_c) == {{(CNT_W-1){1'b0}}, 1'b1}"
    " || (cnt_s - cnt_c) == {CNT_W{1'b1}})",
}
# the map's key of an internal of the table ("register_file.pw" -> registers, "internals.kon"
# -> internals "kon"); next-state nets and candidates have none
MAP_SECTIONS = ("registers", "internals")


def map_key(source):
    """(section, key) of the map entry that names a table source, or None."""
    if source.startswith("internals."):
        return ("internals", source.split(".", 1)[1])
    if re.fullmatch(
        r"(action_switching\.sync|timing_generator\.tmr|comparator_latch\.vld"
        r"|register_file\.(adaptive|pw|pi|ps|si_max|si_min|t1|t2|cth|smp_on))",
        source,
    ):
        return ("registers", source)
    return None


def read_map(path):
    """{(section, key): RTL path} of a map file; bad input is a SetupError naming the field."""
    try:
        with open(path, "rb") as f:
            doc = tomllib.load(f)
    except (OSError, ValueError) as e:
        raise SetupError("cannot read the map %s: %s" % (path, e)) from e
    out = {}
    for sec, table in doc.items():
        if sec not in MAP_SECTIONS or not isinstance(table, dict):
            raise SetupError(
                "%s: [%s] is not a section of a map (valid: %s)"
                % (path, sec, ", ".join(MAP_SECTIONS))
            )
        for k, v in table.items():
            if not isinstance(v, str) or not re.fullmatch(
                r"[A-Za-z_]\w*(\.[A-Za-z_]\w*(\[\d+\])*)+", v
            ):
                raise SetupError(
                    '%s: [%s] %s = %r: expected "top.instance.signal" (fields of packed structs '
                    "and [index] allowed)" % (path, sec, k, v)
                )
            out[(sec, k)] = v
    return out


def dependencies(path=MONITOR):
    """(inputs, {hit wire: set of the monitor's inputs and parameters it reads}) from the
    monitor's text."""
    text = re.sub(r"//[^\n]*|/\*.*?\*/", "", open(path).read(), flags=re.S)
    head, _, body = text.partition(");")
    inputs = re.findall(r"input\s+wire\s+(?:\[[^\]]*\]\s*)?(\w+)", head)
    params = re.findall(r"parameter\s+integer\s+(\w+)", head)
    deps = {}
    lit = re.compile(r"\d*'[sS]?[bBoOdDhH][0-9a-fA-FxXzZ_]+")
    for st in body.split(";"):
        m = re.match(r"\s*(?:wire|localparam)\s*(?:\[[^\]]*\]\s*)?(\w+)\s*=(.*)$", st, re.S)
        if m:
            deps[m.group(1)] = set(re.findall(r"\b[A-Za-z_]\w*\b", lit.sub(" ", m.group(2))))
    deps.setdefault("started", set()).add("rst_n")
    leaves = set(inputs) | set(params)
    memo = {}

    def cone(n, seen=()):
        if n in memo:
            return memo[n]
        if n in leaves:
            return {n}
        out = set()
        for x in deps.get(n, ()):
            if x != n and x not in seen:
                out |= cone(x, seen + (n,))
        memo[n] = out
        return out

    return inputs, {w: cone(w) for w in deps if w.startswith("hit_")}


def bindings(table, mapping):
    """{monitor input: (how, Verilog expression, map entry or None)} with `how` one of port,
    map, ports (rebuilt from the ports), next (the port one edge later), none."""
    out = {}
    for s in table["signals"]:
        name, src = s["name"], s["source"]
        if src == "port":
            out[name] = ("port", name, None)
            continue
        key = map_key(src)
        if key and key in mapping:
            path = mapping[key]
            out[name] = ("map", "dut." + path.split(".", 1)[1], key)
        elif name in FROM_VIEW:
            out[name] = ("ports", "pv_%s" % name, key)
        elif name in FROM_NEXT:
            out[name] = ("next", FROM_NEXT[name], key)
        else:
            out[name] = ("none", None, key)
    return out


def entry_text(key):
    sec, k = key
    return '[%s] "%s" = "pmu50...."' % (sec, k)


def width_decl(w):
    if w == "1":
        return ""
    return "[%s:0] " % (int(w) - 1) if w.isdigit() else "[%s-1:0] " % w


def bind_top(name, table, bind, contract, defaults, checks=(), lemma_nets=(), lemmas=(), sim=False):
    """The text of a top `name` that instantiates the DUT `pmu50`, pmu50_port_view over its
    ports and the monitor bound by `bind` (bindings()), one cycle behind the DUT. Formal (sim
    False): inputs are the contract's inputs without rst_n, reset in cycle 0 (f_started), the
    lemma nets ([(name, width, binding)]) and assertions `lemmas` ({label: expr}, on the DUT's
    current values), and `checks` [(label, assert|cover, bin index)] on the monitor's hits.
    Simulation (sim True): the contract's ports and `hits`, as pmu50_cov_top."""
    c = contract
    n = len(table["bins"])
    params = ",\n".join("    parameter integer %s = %d" % kv for kv in defaults.items())
    ins = [p for p in c["ports"] if p["direction"] == "in" and (sim or p["name"] != c["reset"])]
    outs = [p for p in c["ports"] if p["direction"] == "out"]

    def rng(p):
        w = p["width"]
        return "" if w == 1 else ("[%d:0] " % (w - 1) if isinstance(w, int) else "[%s-1:0] " % w)

    free = sorted(k for k, b in bind.items() if b[0] == "none")
    sigw = {s["name"]: s["width"] for s in table["signals"]}
    ports = ["    input wire %s%s" % (rng(p), p["name"]) for p in ins]
    if sim:
        ports += ["    output wire %s%s" % (rng(p), p["name"]) for p in outs]
        ports += ["    output wire [%d:0] hits" % (n - 1)]
    else:
        # the internals nothing binds: free inputs (the bins that read them are not checked)
        ports += ["    input wire %sfree_%s" % (width_decl(sigw[k]), k) for k in free]
    L = [
        "// GENERATED by hdl/formal/pmu50_formal/bind.py: the coverage monitor bound to an RTL",
        "`default_nettype none",
        "module %s #(\n%s,\n    parameter integer CLOCK_NS = 10000\n) (" % (name, params),
        ",\n".join(ports),
        ");",
    ]
    if not sim:
        L += [
            "    reg f_started = 1'b0;",
            "    always @(posedge %s) f_started <= 1'b1;" % c["clock"],
            "    wire %s = f_started;" % c["reset"],
        ]
        L += ["    wire %s%s;" % (rng(p), p["name"]) for p in outs]
    plist = ", ".join(".%s(%s)" % (k, k) for k in defaults)
    L += [
        "    %s #(%s) dut (%s);"
        % (c["top"], plist, ", ".join(".%s(%s)" % (p["name"], p["name"]) for p in c["ports"])),
        "    // the internals rebuilt from the ports (docs/spec.md)",
    ]
    view_outs = sorted(FROM_VIEW)
    L += [
        "    wire %spv_%s;" % (width_decl(sigw.get(v, "16") if v in sigw else "16"), v)
        for v in view_outs
    ]
    L += [
        "    pmu50_port_view #(%s) pv (" % plist,
        "        "
        + ", ".join(
            ".%s(%s)" % (p, p)
            for p in (
                "clk",
                "rst_n",
                "ig",
                "cmp_s",
                "cmp_c",
                "bus_we",
                "bus_addr",
                "bus_wdata",
                "sig",
                "smp",
                "sr",
                "cs",
                "cc",
                "si",
            )
        )
        + ",",
        "        " + ", ".join(".%s(pv_%s)" % (v, v) for v in view_outs),
        "    );",
        "    // the monitor one cycle behind the DUT: every input through a flop, the next-state",
        "    // nets as the ports they became",
        "    reg d_valid;",
        "    always @(posedge clk or negedge rst_n)",
        "        if (!rst_n) d_valid <= 1'b0;",
        "        else        d_valid <= 1'b1;",
    ]
    conns = []
    for s in table["signals"]:
        k, w = s["name"], width_decl(s["width"])
        how, expr, _ = bind[k]
        if k == c["reset"]:
            conns.append(".%s(d_valid)" % k)
            continue
        if how == "next":
            L.append("    wire %sm_%s = %s;" % (w, k, expr))
        elif how == "none":
            L.append("    wire %sm_%s = %s;" % (w, k, "free_" + k if not sim else "'0"))
        else:
            L.append("    reg %sm_%s;" % (w, k))
            L.append("    always @(posedge clk) m_%s <= %s;" % (k, expr))
        conns.append(".%s(m_%s)" % (k, k))
    L += [
        "    wire [%d:0] mhits;" % (n - 1),
        "    pmu50_cov #(.SYNC_DEPTH(SYNC_DEPTH), .CNT_W(CNT_W), .CLOCK_NS(CLOCK_NS)) cov (",
        "        .clk(clk), " + ", ".join(conns) + ", .hits(mhits));",
    ]
    if sim:
        L.append("    assign hits = mhits;")
    else:
        for ln, w, b in lemma_nets:
            L.append("    wire [%d:0] %s = %s;" % (w - 1, ln, b))
        L.append("    always @* begin")
        for lab, expr in lemmas.items():
            L.append("        if (f_started) %s: assert (%s);" % (lab, expr))
        for lab, kind, i in checks:
            L.append(
                "        %s: %s (%smhits[%d]);" % (lab, kind, "!" if kind == "assert" else "", i)
            )
        L.append("    end")
    L += ["endmodule", "`default_nettype wire", ""]
    return "\n".join(L)
