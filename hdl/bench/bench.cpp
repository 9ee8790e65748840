// Speed harness of the Verilog twin under Verilator, for `make bench` (benches/compare.sh).
//
//   bench FILE.vec REPS [--trace OUT.vcd]
//
// Reads the input columns of a vector file (`pmu50 vectors`, docs/spec.md 6.2) into memory, then
// replays them REPS times from reset, one rising edge per line, and prints
//
//   ticks=<REPS x lines> cpu_s=<process CPU seconds of the replay loop> checksum=<hex>
//
// The checksum folds the 23 outputs after every edge exactly as benches/compare/stim.rs does for
// the Rust model (pack and mix below), over the last repetition; equal checksums mean equal
// outputs.
// With --trace (a build with `verilator --trace`) the traced signals of the twin are dumped once
// per tick (after the rising edge, time = tick x clock period) into OUT.vcd: build.sh passes
// hdl/bench/trace.vlt, which traces the counterparts of the Rust tracer's 65 signals only.
//
// Build: hdl/bench/build.sh (verilator -O3, g++ -O3, the file's parameters as -G values, so the
// programmable registers reset to the scenario's values without any deposit).
#include "Vpmu50.h"
#include "verilated.h"
#if VM_TRACE
#include "verilated_vcd_c.h"
#endif

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

namespace {

struct In {
    uint8_t bits;  // ig, vs2_ok, cmp_s, cmp_c, bus_we (bit 0..4)
    uint8_t addr;
    uint16_t wdata;
};

double cpu_now() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

// The 23 outputs after an edge, packed into two words (the same packing as benches/compare/stim.rs).
inline uint64_t mix(uint64_t h, const Vpmu50 *t) {
    uint64_t flags = uint64_t(t->sig) | uint64_t(t->vr_hi) << 1 | uint64_t(t->vm_en) << 2 | uint64_t(t->vs1_en) << 3 |
                     uint64_t(t->vs2_en) << 4 | uint64_t(t->vp_en) << 5 | uint64_t(t->rail_hi) << 6 | uint64_t(t->st) << 7 |
                     uint64_t(t->sr) << 8 | uint64_t(t->ps_win) << 9 | uint64_t(t->smp) << 10 | uint64_t(t->cs) << 11 |
                     uint64_t(t->cc) << 12 | uint64_t(t->hist_s) << 13 | uint64_t(t->hist_c) << 14 | uint64_t(t->diag) << 15 |
                     uint64_t(t->quadrant_skip) << 16 | uint64_t(t->bus_err) << 17;
    uint64_t w0 = flags | uint64_t(t->cnt_r) << 18 | uint64_t(t->si) << 26 | uint64_t(t->bus_rdata) << 42;
    uint64_t w1 = uint64_t(t->cnt_s) | uint64_t(t->cnt_c) << 16;
    return ((h << 5 | h >> 59) ^ w0) + w1 * 0x9E3779B97F4A7C15ull;
}

}  // namespace

int main(int argc, char **argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s FILE.vec REPS [--trace OUT.vcd]\n", argv[0]);
        return 2;
    }
    const char *path = argv[1];
    long reps = std::strtol(argv[2], nullptr, 10);
    // a VCD holds one replay (time restarts with every replay)
    const char *trace = nullptr;
    for (int i = 3; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--trace") && i + 1 < argc) trace = argv[++i];
    }
    FILE *fp = std::fopen(path, "r");
    if (trace && reps != 1) {
        std::fprintf(stderr, "bench: --trace needs REPS = 1\n");
        return 2;
    }
    if (!fp || reps < 1) {
        std::fprintf(stderr, "bench: cannot read %s or bad REPS\n", path);
        return 2;
    }
    std::vector<In> in;
    long clock_ns = 10000;
    char line[512];
    while (std::fgets(line, sizeof line, fp)) {
        if (line[0] == '/') {
            std::sscanf(line, "// clock_ns %ld", &clock_ns);
            continue;
        }
        unsigned f[7];
        if (std::sscanf(line, "%x %x %x %x %x %x %x", &f[0], &f[1], &f[2], &f[3], &f[4], &f[5], &f[6]) != 7) continue;
        in.push_back(In{uint8_t((f[0] & 1) | (f[1] & 1) << 1 | (f[2] & 1) << 2 | (f[3] & 1) << 3 | (f[4] & 1) << 4), uint8_t(f[5]),
                        uint16_t(f[6])});
    }
    std::fclose(fp);

    auto ctx = std::make_unique<VerilatedContext>();
    auto top = std::make_unique<Vpmu50>(ctx.get(), "pmu50");
    const uint64_t unit = clock_ns % 1000 == 0 ? 1000 : 1;  // VCD time in us when possible
#if VM_TRACE
    std::unique_ptr<VerilatedVcdC> tfp;
    if (trace) {
        ctx->traceEverOn(true);
        tfp = std::make_unique<VerilatedVcdC>();
        top->trace(tfp.get(), 99);
        // the $timescale of the times dumped below (Verilator's default says 1ps)
        tfp->set_time_resolution(unit == 1000 ? "1us" : "1ns");
        tfp->open(trace);
    }
#else
    if (trace) {
        std::fprintf(stderr, "bench: this build has no tracing (build with --trace)\n");
        return 2;
    }
#endif
    uint64_t h = 0;
    double t0 = cpu_now();
    for (long r = 0; r < reps; ++r) {
        // Power-on reset: a falling edge of rst_n (the asynchronous reset is edge-triggered).
        top->clk = 0;
        top->rst_n = 1;
        top->eval();
        top->rst_n = 0;
        top->eval();
        top->rst_n = 1;
        top->eval();
        h = 0;
        uint64_t k = 0;
        for (const In &x : in) {
            top->ig = x.bits & 1;
            top->vs2_ok = (x.bits >> 1) & 1;
            top->cmp_s = (x.bits >> 2) & 1;
            top->cmp_c = (x.bits >> 3) & 1;
            top->bus_we = (x.bits >> 4) & 1;
            top->bus_addr = x.addr;
            top->bus_wdata = x.wdata;
            top->clk = 1;
            top->eval();
            ++k;
            h = mix(h, top.get());
#if VM_TRACE
            if (tfp) tfp->dump(k * uint64_t(clock_ns) / unit);
#endif
            top->clk = 0;
            top->eval();
        }
    }
#if VM_TRACE
    if (tfp) tfp->close();
#endif
    double t1 = cpu_now();
    top->final();
    std::printf("ticks=%" PRIu64 " cpu_s=%.6f checksum=%016" PRIx64 "\n", uint64_t(reps) * in.size(), t1 - t0, h);
    return 0;
}
