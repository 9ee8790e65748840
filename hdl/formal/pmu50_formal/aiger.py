"""Binary AIGER (1.9) models of the formal kit: read once per parameter set, cut per check.

yosys writes one model per parameter set in which every check (assertion or reachability cover)
is an output (kit.py turns each `$assert`/`$cover` cell into an output first).
`Aiger.cone(k)` keeps the logic that output k and the invariant constraints (the `assume`s of
the RTL) depend on, and returns a model whose only bad-state property is that output: what
yosys' `opt_clean` did per property before, in milliseconds instead of a yosys run.
"""


class AigerError(Exception):
    pass


def _varint(data, pos):
    x, shift = 0, 0
    while True:
        if pos >= len(data):
            raise AigerError("truncated AND section")
        b = data[pos]
        pos += 1
        x |= (b & 0x7F) << shift
        if not b & 0x80:
            return x, pos
        shift += 7


def _put_varint(out, x):
    while x & ~0x7F:
        out.append((x & 0x7F) | 0x80)
        x >>= 7
    out.append(x)


class Aiger:
    def __init__(self, data):
        nl = data.index(b"\n")
        head = data[:nl].split()
        if not head or head[0] != b"aig":
            raise AigerError("not a binary AIGER file (header %r)" % data[:40])
        nums = [int(x) for x in head[1:]] + [0] * 9
        self.m, self.i, self.l, self.o, self.a, self.b, self.c = nums[:7]
        if nums[7] or nums[8]:
            raise AigerError("justice/fairness sections are not supported")
        pos = nl + 1
        lines = []
        for _ in range(self.l + self.o + self.b + self.c):
            e = data.index(b"\n", pos)
            lines.append([int(x) for x in data[pos:e].split()])
            pos = e + 1
        self.latches = lines[: self.l]  # [next, (init)]
        self.outputs = [x[0] for x in lines[self.l : self.l + self.o]]
        self.bad = [x[0] for x in lines[self.l + self.o : self.l + self.o + self.b]]
        self.constraints = [x[0] for x in lines[self.l + self.o + self.b :]]
        self.ands = []  # (rhs0, rhs1) of var I+L+1+k
        for k in range(self.a):
            lhs = 2 * (self.i + self.l + 1 + k)
            d0, pos = _varint(data, pos)
            d1, pos = _varint(data, pos)
            r0 = lhs - d0
            self.ands.append((r0, r0 - d1))

    def held(self, bits):
        """AIGER bytes of this model with some inputs held at constants: `bits` maps an input's
        index (0-based) to 0 or 1. The inputs stay (unread), so a witness's input lines keep
        their columns; the engines' constant propagation removes the logic that no longer
        moves."""
        for k, b in bits.items():
            if not 0 <= k < self.i or b not in (0, 1):
                raise AigerError(
                    "held input %r=%r: the model has inputs 0..%d, values 0 or 1"
                    % (k, b, self.i - 1)
                )
        const = {k + 1: b for k, b in bits.items()}

        def sub(x):
            v = x >> 1
            return (const[v] ^ (x & 1)) if v in const else x

        out = bytearray(
            b"aig %d %d %d %d %d %d %d\n" % (self.m, self.i, self.l, self.o, self.a, self.b, self.c)
        )
        for lt in self.latches:
            out += b" ".join(b"%d" % x for x in [sub(lt[0])] + lt[1:]) + b"\n"
        for x in self.outputs + self.bad + self.constraints:
            out += b"%d\n" % sub(x)
        first_and = self.i + self.l + 1
        for k, (r0, r1) in enumerate(self.ands):
            a0, a1 = sub(r0), sub(r1)
            if a0 < a1:
                a0, a1 = a1, a0
            _put_varint(out, 2 * (first_and + k) - a0)
            _put_varint(out, a0 - a1)
        return bytes(out)

    def cone(self, lit):
        """(AIGER bytes with `lit` as its one bad-state property and every constraint kept,
        {old latch index: new latch index})."""
        first_and = self.i + self.l + 1
        need = set()
        todo = [lit >> 1] + [c >> 1 for c in self.constraints]
        while todo:
            v = todo.pop()
            if v in need or v == 0:
                continue
            need.add(v)
            if v > self.i and v < first_and:
                todo.append(self.latches[v - self.i - 1][0] >> 1)
            elif v >= first_and:
                r0, r1 = self.ands[v - first_and]
                todo += [r0 >> 1, r1 >> 1]
        # new numbering: every input kept (a witness's input lines stay valid), then the needed
        # latches and AND gates in their old (topological) order
        new = {0: 0}
        for v in range(1, self.i + 1):
            new[v] = v
        latch_map = {}
        nv = self.i
        for k in range(self.l):
            if self.i + 1 + k in need:
                nv += 1
                new[self.i + 1 + k] = nv
                latch_map[k] = len(latch_map)
        and_vars = [v for v in range(first_and, first_and + self.a) if v in need]
        for v in and_vars:
            nv += 1
            new[v] = nv

        def tr(x):
            return 2 * new[x >> 1] + (x & 1)

        nl = len(latch_map)
        out = bytearray(
            b"aig %d %d %d 0 %d 1 %d\n" % (nv, self.i, nl, len(and_vars), len(self.constraints))
        )
        for k in sorted(latch_map):
            lt = self.latches[k]
            out += b" ".join(b"%d" % x for x in [tr(lt[0])] + lt[1:]) + b"\n"
        out += b"%d\n" % tr(lit)
        for c in self.constraints:
            out += b"%d\n" % tr(c)
        for v in and_vars:
            r0, r1 = self.ands[v - first_and]
            lhs, a0, a1 = 2 * new[v], tr(r0), tr(r1)
            if a0 < a1:
                a0, a1 = a1, a0
            _put_varint(out, lhs - a0)
            _put_varint(out, a0 - a1)
        return bytes(out), latch_map


def cone_map(aim_text, latch_map):
    """The yosys map file (-map) of the full model rewritten for a cone: inputs and init
    inputs as they were, latches renumbered, latches outside the cone dropped."""
    out = []
    for line in aim_text.splitlines():
        f = line.split()
        if f and f[0] == "latch":
            k = int(f[1])
            if k in latch_map:
                out.append(" ".join(["latch", str(latch_map[k])] + f[2:]))
        elif f and f[0] in ("input", "init"):
            out.append(line)
    return "\n".join(out) + "\n"
