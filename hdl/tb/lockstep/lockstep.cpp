// Lockstep co-simulation (verification method 2): the Verilog twin (Verilator) and the Rust
// reference model (C ABI, hdl/ffi/include/pmu50.h) run side by side on the INPUT columns of a
// vector file; after every rising edge all outputs and registers are compared, and before every
// edge the combinational internals (scope `internals`). The expected-output columns of the file
// are not used: the model computes them live. This file only feeds values: the comparison and
// its MISMATCH lines are the model's (pmu50_check), shared with the SystemVerilog bench.
//
// Usage: lockstep FILE.vec [--history N] [--max-ticks N]
// Exit:  0 no divergence (prints `PASS ticks=<n> ...`), 1 divergence (report on stdout),
//        2 bad input (unreadable file, illegal parameters, build/file structural mismatch).
//
// Build (hdl/scripts/build_lockstep.sh does this): one Verilator model per
// (mutant, SYNC_DEPTH, CNT_W), compiled with -DPMU50_SYNC_DEPTH=.. -DPMU50_CNT_W=..; the reset
// values of the programmable registers come from the vector header at run time: they are
// deposited into the twin's registers right after reset (lockstep.vlt makes them writable).
#include "twin_access.h"
#include "verilated.h"

#include "pmu50.h"

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#ifndef PMU50_SYNC_DEPTH
#define PMU50_SYNC_DEPTH 2
#endif
#ifndef PMU50_CNT_W
#define PMU50_CNT_W 16
#endif
#ifndef PMU50_MUTANT
#define PMU50_MUTANT "none"
#endif

namespace {

constexpr int kFields = PMU50_INPUT_COUNT + PMU50_OUTPUT_COUNT;

struct Header {
    std::map<std::string, long> param;
    long clock_ns = 10000;
    long ticks = -1;
    long fields = kFields;
    std::string scenario = "?";
};

struct HistoryRow {
    uint64_t tick;  // edge number the inputs were applied for
    pmu50_inputs in;
    pmu50_outputs model_after;
};

void die(int code, const char *fmt, const char *a = "", const char *b = "") {
    std::printf("LOCKSTEP ERROR: ");
    std::printf(fmt, a, b);
    std::printf("\n");
    std::exit(code);
}

// Parse whitespace-separated hex fields of one data line.
int parse_fields(const char *s, uint32_t *f, int max) {
    int n = 0;
    while (*s) {
        while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n') ++s;
        if (!*s) break;
        char *end = nullptr;
        unsigned long v = std::strtoul(s, &end, 16);
        if (end == s) return -1;
        if (n < max) f[n] = static_cast<uint32_t>(v);
        ++n;
        s = end;
    }
    return n;
}

template <typename T> uint64_t u(const T &v) { return static_cast<uint64_t>(v); }

}  // namespace

int main(int argc, char **argv) {
    const char *path = nullptr;
    size_t history = 8;
    long max_ticks = -1;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--history" && i + 1 < argc) history = std::strtoul(argv[++i], nullptr, 10);
        else if (a == "--max-ticks" && i + 1 < argc) max_ticks = std::strtol(argv[++i], nullptr, 10);
        else if (a == "-h" || a == "--help") {
            std::printf("usage: %s FILE.vec [--history N] [--max-ticks N]\n", argv[0]);
            return 0;
        } else if (a.rfind("+", 0) == 0) {
            // Verilator plusargs are ignored
        } else if (!path) path = argv[i];
        else die(2, "unexpected argument `%s`", argv[i]);
    }
    if (!path) die(2, "usage: lockstep FILE.vec [--history N] [--max-ticks N]");

    FILE *fp = std::fopen(path, "r");
    if (!fp) die(2, "cannot open `%s`: %s", path, std::strerror(errno));

    // ------------------------------------------------------------------ header
    Header h;
    std::vector<char> buf(1 << 16);
    std::string first_data;
    long line_no = 0;
    while (std::fgets(buf.data(), static_cast<int>(buf.size()), fp)) {
        ++line_no;
        const char *l = buf.data();
        while (*l == ' ' || *l == '\t') ++l;
        if (*l == '\n' || *l == '\r' || *l == 0) continue;
        if (l[0] == '/' && l[1] == '/') {
            char name[128];
            long v;
            if (std::sscanf(l, "// param %127s %ld", name, &v) == 2) h.param[name] = v;
            else if (std::sscanf(l, "// clock_ns %ld", &v) == 1) h.clock_ns = v;
            else if (std::sscanf(l, "// ticks %ld", &v) == 1) h.ticks = v;
            else if (std::sscanf(l, "// fields %ld", &v) == 1) h.fields = v;
            else if (std::sscanf(l, "// scenario %127s", name) == 1) h.scenario = name;
            continue;
        }
        first_data = l;
        break;
    }
    if (h.fields != kFields) die(2, "`%s`: header says fields %s, expected PMU50_INPUT_COUNT + PMU50_OUTPUT_COUNT", path, std::to_string(h.fields).c_str());
    if (h.param.count("CLOCK_US")) h.clock_ns = h.param["CLOCK_US"] * 1000;

    pmu50_params p;
    pmu50_params_default(&p);
    auto take = [&](const char *n, auto &field) {
        auto it = h.param.find(n);
        if (it != h.param.end()) field = static_cast<std::remove_reference_t<decltype(field)>>(it->second);
    };
    take("SYNC_DEPTH", p.sync_depth);
    take("CNT_W", p.cnt_width);
#define TAKE(P, n) take(#P, p.n);
    TWIN_RESET_VALUES(TAKE)
#undef TAKE
    if (p.sync_depth != PMU50_SYNC_DEPTH || p.cnt_width != PMU50_CNT_W) {
        std::printf("LOCKSTEP ERROR: `%s` needs SYNC_DEPTH=%d CNT_W=%d, this binary was built for SYNC_DEPTH=%d CNT_W=%d "
                    "(rebuild: hdl/scripts/build_lockstep.sh <mutant> %d %d)\n",
                    path, p.sync_depth, p.cnt_width, PMU50_SYNC_DEPTH, PMU50_CNT_W, p.sync_depth, p.cnt_width);
        return 2;
    }

    // ------------------------------------------------------------------ the two cores
    pmu50_t *model = pmu50_new(&p);
    if (!model) die(2, "illegal parameters in `%s`: %s", path, pmu50_last_error());
    std::unique_ptr<pmu50_t, void (*)(pmu50_t *)> model_guard(model, pmu50_free);

    auto ctx = std::make_unique<VerilatedContext>();
    ctx->commandArgs(argc, argv);
    auto top = std::make_unique<Vpmu50>(ctx.get(), "pmu50");
    Vpmu50___024root *R = top->rootp;

    // The twin's values in the order of the model's tables (twin_access.h), checked by name.
    for (int k = 0; k < twin::kRegisters; ++k) {
        if (pmu50_reg_find(twin::kRegisterNames[k]) != k) die(2, "the model's register %s is not at the twin's index", twin::kRegisterNames[k]);
    }
    for (int k = 0; k < twin::kOutputs; ++k) {
        const char *name = nullptr;
        uint8_t width = 0;
        if (pmu50_output_info(model, k, &name, &width) != PMU50_OK || std::strcmp(name, twin::kOutputNames[k]) != 0)
            die(2, "the model's output %s is not at the twin's index", twin::kOutputNames[k]);
    }
    if (static_cast<size_t>(twin::kRegisters) != pmu50_reg_count() || static_cast<size_t>(twin::kOutputs) != pmu50_output_count() ||
        static_cast<size_t>(twin::kInternals) != pmu50_internal_count())
        die(2, "the model's signal table and twin_access.h differ in length");
    uint64_t rtl_regs[twin::kRegisters];
    auto twin_registers = [&] { twin::registers(R, rtl_regs); };
    auto twin_outputs = [&](pmu50_outputs &o) {
        uint64_t v[twin::kOutputs];
        twin::outputs(*top, v);
        for (int k = 0; k < twin::kOutputs; ++k) pmu50_output_set(&o, k, v[k]);
    };
    auto twin_internals = [&](pmu50_internals &x) {
        uint64_t v[twin::kInternals];
        twin::internals(R, v);
        for (int k = 0; k < twin::kInternals; ++k) pmu50_internal_set(&x, k, v[k]);
    };
    auto set_inputs = [&](const pmu50_inputs &in) {
#define VALUE(n) uint64_t{in.n},
        const uint64_t v[twin::kInputs] = {TWIN_INPUTS(VALUE)};
#undef VALUE
        twin::set_inputs(*top, v);
    };

    // The comparison itself is the model's: pmu50_check. >0 mismatches, <0 error.
    auto check = [&](const pmu50_outputs *ro, const uint64_t *rr, const pmu50_internals *rx) {
        int n = pmu50_check(model, ro, rr, rx);
        if (n < 0) {
            std::printf("LOCKSTEP ERROR: pmu50_check: %s\n", pmu50_last_error());
            std::exit(2);
        }
        return n;
    };

    std::deque<HistoryRow> hist;
    auto report = [&](uint64_t tick, const pmu50_inputs *during) {
        std::printf("%s", pmu50_check_report(model));
        if (during)
            std::printf("LOCKSTEP FAIL %s (scenario %s, mutant %s): first divergence at tick %" PRIu64
                        " (combinational, before rising edge %" PRIu64 "), time %" PRIu64 " ns\n",
                        path, h.scenario.c_str(), PMU50_MUTANT, tick, tick + 1, tick * static_cast<uint64_t>(h.clock_ns));
        else
            std::printf("LOCKSTEP FAIL %s (scenario %s, mutant %s): first divergence at tick %" PRIu64
                        " (after rising edge %" PRIu64 "), time %" PRIu64 " ns\n",
                        path, h.scenario.c_str(), PMU50_MUTANT, tick, tick, tick * static_cast<uint64_t>(h.clock_ns));
        std::printf("last %zu ticks: inputs applied in tick k-1 (sampled at edge k), model outputs after edge k\n", hist.size());
        std::printf("  %8s | ig ok s c we ad wdat | sig st sr smp cs cc cnt_s cnt_c cnt_r   si hs hc dg qs rdat er\n", "edge k");
        for (const auto &r : hist) {
            const auto &i = r.in;
            const auto &o = r.model_after;
            std::printf("  %8" PRIu64 " |  %u  %u %u %u  %u %02x %04x |  %u   %u  %u  %u   %u  %u  %04x  %04x    %02x %04x  %u  %u  %u  %u %04x  %u\n",
                        r.tick, i.ig, i.vs2_ok, i.cmp_s, i.cmp_c, i.bus_we, i.bus_addr, i.bus_wdata, o.sig, o.st, o.sr,
                        o.smp, o.cs, o.cc, o.cnt_s, o.cnt_c, o.cnt_r, o.si, o.hist_s, o.hist_c, o.diag,
                        o.quadrant_skip, o.bus_rdata, o.bus_err);
        }
        if (during) {
            const auto &i = *during;
            std::printf("  %8" PRIu64 " |  %u  %u %u %u  %u %02x %04x | (edge not taken: divergence before it)\n", tick + 1,
                        i.ig, i.vs2_ok, i.cmp_s, i.cmp_c, i.bus_we, i.bus_addr, i.bus_wdata);
        }
    };

    // ------------------------------------------------------------------ reset
    {
        // The scenario's reset values (the build's parameters are the defaults).
#define VALUE(P, n) uint64_t{p.n},
        const uint64_t v[twin::kResetValues] = {TWIN_RESET_VALUES(VALUE)};
#undef VALUE
        twin::reset(*top, v);
    }

    // Tick 0: reset state.
    {
        pmu50_outputs ro;
        twin_outputs(ro);
        twin_registers();
        if (check(&ro, rtl_regs, nullptr) > 0) {
            report(0, nullptr);
            return 1;
        }
    }

    // ------------------------------------------------------------------ run
    uint64_t tick = 0;
    uint32_t f[kFields];
    std::string pending = first_data;
    bool have = !pending.empty();
    while (have) {
        if (max_ticks >= 0 && static_cast<long>(tick) >= max_ticks) break;
        int n = parse_fields(pending.c_str(), f, kFields);
        if (n != kFields) {
            std::printf("LOCKSTEP ERROR: `%s` line %ld: %d fields, expected %d\n", path, line_no, n, kFields);
            return 2;
        }
        pmu50_inputs in{};
        in.ig = f[0] & 1; in.vs2_ok = f[1] & 1; in.cmp_s = f[2] & 1; in.cmp_c = f[3] & 1;
        in.bus_we = f[4] & 1; in.bus_addr = static_cast<uint8_t>(f[5]); in.bus_wdata = static_cast<uint16_t>(f[6]);

        // cycle `tick`: inputs applied, combinational logic settles
        set_inputs(in);
        top->eval();
        pmu50_outputs mo;
        if (pmu50_step_traced(model, &in, nullptr, &mo) != PMU50_OK) {
            std::printf("LOCKSTEP ERROR: model step failed: %s\n", pmu50_last_error());
            return 2;
        }
        pmu50_internals rx;
        twin_internals(rx);
        if (check(nullptr, nullptr, &rx) > 0) {
            // visible during tick `tick`, before rising edge tick+1 (as in the VCDs)
            report(tick, &in);
            return 1;
        }
        // rising edge tick+1
        top->clk = 1;
        top->eval();
        ++tick;
        pmu50_outputs ro;
        twin_outputs(ro);
        twin_registers();
        int nm = check(&ro, rtl_regs, nullptr);
        hist.push_back({tick, in, mo});
        if (hist.size() > history) hist.pop_front();
        if (nm > 0) {
            report(tick, nullptr);
            return 1;
        }
        top->clk = 0;
        top->eval();

        // next line
        have = false;
        while (std::fgets(buf.data(), static_cast<int>(buf.size()), fp)) {
            ++line_no;
            const char *l = buf.data();
            while (*l == ' ' || *l == '\t') ++l;
            if (*l == '\n' || *l == '\r' || *l == 0 || (l[0] == '/' && l[1] == '/')) continue;
            pending = l;
            have = true;
            break;
        }
    }
    std::fclose(fp);
    if (max_ticks < 0 && h.ticks >= 0 && static_cast<long>(tick) != h.ticks) {
        std::printf("LOCKSTEP ERROR: `%s` has %" PRIu64 " vector lines, header says ticks %ld\n", path, tick, h.ticks);
        return 2;
    }
    top->final();
    std::printf("PASS ticks=%" PRIu64 " outputs=%zu registers=%zu internals=%zu (scenario %s, mutant %s)\n", tick,
                    pmu50_output_count(), pmu50_reg_count(), pmu50_internal_count(), h.scenario.c_str(), PMU50_MUTANT);
    return 0;
}
