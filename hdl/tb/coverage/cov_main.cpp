// The coverage monitor (hdl/formal/pmu50_cov.sv) over the twin, as a filter: one Verilator build
// of pmu50_cov_top (hdl/formal/pmu50_cov_top.sv) for one set of Verilog parameters (-G).
//
// stdin: one line per tick, the inputs applied at its clock edge in the columns of a vector file
// (docs/spec.md 6.2): ig vs2_ok cmp_s cmp_c bus_we bus_addr bus_wdata, hex; anything after them
// and lines starting with `//` are ignored.
// stdout: one line per tick, the monitor's `hits` before that edge (bit i = bin i of the model,
// hdl/formal/pmu50_cov.json), hex, most significant digit first.
//
// With --first-hits: one line per bin hit at least once, at the end instead: the bin's index and
// the first tick (0 = the first line) before whose edge it was hit, decimal
// (hdl/formal/coverage.py replays its long witnesses so).
//
// Reset: rst_n falls and is held low for one evaluation, then released; the first line is the first edge out of reset,
// as the model's first step.
#include "Vpmu50_cov_top.h"
#include "verilated.h"

#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

int main(int argc, char **argv) {
    auto ctx = std::make_unique<VerilatedContext>();
    ctx->commandArgs(argc, argv);
    auto top = std::make_unique<Vpmu50_cov_top>(ctx.get(), "pmu50_cov_top");
    // a falling edge of rst_n (the asynchronous reset acts on it), held for one evaluation
    top->clk = 0;
    top->rst_n = 1;
    top->eval();
    top->rst_n = 0;
    top->eval();
    top->rst_n = 1;
    top->eval();
    const int words = static_cast<int>(sizeof(top->hits) / sizeof(top->hits[0]));
    const int bits = static_cast<int>(HITS_BITS);
    bool first_hits = false;
    for (int a = 1; a < argc; ++a) {
        if (std::strcmp(argv[a], "--first-hits") == 0) first_hits = true;
    }
    std::vector<long> first(bits, -1);
    char line[4096];
    std::string out;
    unsigned long tick = 0;
    while (std::fgets(line, sizeof line, stdin)) {
        if (line[0] == '/' || line[0] == '\n') continue;
        unsigned ig, ok, s, c, we, addr, data;
        if (std::sscanf(line, "%x %x %x %x %x %x %x", &ig, &ok, &s, &c, &we, &addr, &data) != 7) {
            std::fprintf(stderr, "cov_main: tick %lu: expected 7 hex input columns, got: %s", tick, line);
            return 2;
        }
        top->ig = ig & 1;
        top->vs2_ok = ok & 1;
        top->cmp_s = s & 1;
        top->cmp_c = c & 1;
        top->bus_we = we & 1;
        top->bus_addr = addr & 0xff;
        top->bus_wdata = data & 0xffff;
        top->eval();
        if (first_hits) {
            for (int w = 0; w < words; ++w) {
                if (!top->hits[w]) continue;
                for (int b = 0; b < 32 && w * 32 + b < bits; ++b) {
                    if (((top->hits[w] >> b) & 1) && first[w * 32 + b] < 0) first[w * 32 + b] = static_cast<long>(tick);
                }
            }
        } else {
            out.clear();
            for (int d = (bits + 3) / 4 - 1; d >= 0; --d) {
                const int w = (d * 4) / 32;
                const unsigned nib = w < words ? (top->hits[w] >> ((d * 4) % 32)) & 0xf : 0;
                out.push_back("0123456789abcdef"[nib]);
            }
            out.push_back('\n');
            std::fputs(out.c_str(), stdout);
        }
        top->clk = 1;
        top->eval();
        top->clk = 0;
        top->eval();
        ++tick;
    }
    top->final();
    if (first_hits) {
        for (int b = 0; b < bits; ++b) {
            if (first[b] >= 0) std::printf("%d %ld\n", b, first[b]);
        }
    }
    return 0;
}
