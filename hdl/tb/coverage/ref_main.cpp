// A plain Verilator bench of the contract top `pmu50` that replays a vector file and writes
// Verilator's code coverage of the run: the reference the kit's own code coverage
// (`pmu50 regress --dut verilator --code-coverage`) is compared with, point by point
// (tests/code_coverage_reference.rs). Nothing of the kit is in it: no shared library, no map, no
// lockstep; the build is Verilator's documented one:
//
//   verilator --cc --exe --build -O0 --coverage --top-module pmu50 -G... RTL... ref_main.cpp
//   obj_dir/Vpmu50 OUT.dat < FILE.vec
//
// The vector file (docs/spec.md 6.2): lines starting with `//` are skipped; every other line is
// one tick whose first 7 hex columns are the inputs ig vs2_ok cmp_s cmp_c bus_we bus_addr
// bus_wdata. Reset as a testbench does it: inputs 0, clk low, rst_n falling and held low for one
// evaluation, then released. A tick: the inputs with clk low (one evaluation), then the rising
// edge (one evaluation).
//
// The coverage is written per instance (`forcePerInstance`): a toggle counts the changes of one
// instance's bit, so that changes of two instances of one module are not added into a toggle
// neither instance made.
#include "Vpmu50.h"
#include "verilated.h"
#include "verilated_cov.h"

#include <cstdio>
#include <memory>

int main(int argc, char **argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT.dat < FILE.vec\n", argv[0]);
        return 2;
    }
    auto ctx = std::make_unique<VerilatedContext>();
    auto top = std::make_unique<Vpmu50>(ctx.get(), "pmu50");
    top->clk = 0;
    top->rst_n = 1;
    top->ig = 0;
    top->vs2_ok = 0;
    top->cmp_s = 0;
    top->cmp_c = 0;
    top->bus_we = 0;
    top->bus_addr = 0;
    top->bus_wdata = 0;
    top->eval();
    top->rst_n = 0;
    top->eval();
    top->rst_n = 1;
    top->eval();
    char line[4096];
    unsigned long tick = 0;
    while (std::fgets(line, sizeof line, stdin)) {
        if (line[0] == '/' || line[0] == '\n') continue;
        unsigned ig, ok, s, c, we, addr, data;
        if (std::sscanf(line, "%x %x %x %x %x %x %x", &ig, &ok, &s, &c, &we, &addr, &data) != 7) {
            std::fprintf(stderr, "ref_main: tick %lu: expected 7 hex input columns, got: %s", tick, line);
            return 2;
        }
        top->clk = 0;
        top->ig = ig & 1;
        top->vs2_ok = ok & 1;
        top->cmp_s = s & 1;
        top->cmp_c = c & 1;
        top->bus_we = we & 1;
        top->bus_addr = addr & 0xff;
        top->bus_wdata = data & 0xffff;
        top->eval();
        top->clk = 1;
        top->eval();
        ++tick;
    }
    top->final();
    ctx->coveragep()->forcePerInstance(true);
    ctx->coveragep()->write(argv[1]);
    std::printf("ticks=%lu\n", tick);
    return 0;
}
