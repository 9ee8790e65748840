// The RTL as a shared library for `pmu50 regress --dut verilator` (verification method 2, in
// process): a thin C interface around one Verilator build of the contract top `pmu50`
// (docs/signals.md) for one (SYNC_DEPTH, CNT_W). The regression's DUT worker loads it
// (dlopen), drives it tick by tick from the model's stimulus held in memory and compares every
// output and register after every edge and the internals before it, against the Rust core
// (src/regress/lockstep.rs). No file, no text, no process per seed.
//
// A tick is two evaluations, as the Verilog bench's clock: the inputs of cycle k with clk low
// (the internals of the cycle settle), then the rising edge k+1 (outputs and registers).
//
// Values cross the interface as u64 arrays in the order of the names this library reports
// (pmu50_dut_name), which must be the order of the model's signal table (docs/signals.md): the
// worker checks the names at load time, so an order change on either side is refused instead of
// comparing the wrong pairs.
//
// The twin's names and accessors are those of twin_access.h, shared with lockstep.cpp.
//
// Built by hdl/scripts/build_lockstep.sh with KIND=lib (one translation unit with the
// Verilator output, -fPIC, the Verilator runtime linked in, every symbol hidden but these).
#include "twin_access.h"
#include "verilated.h"

#include <cstdint>
#include <memory>

#define PMU50_DUT_API extern "C" __attribute__((visibility("default")))

#if !defined(PMU50_SYNC_DEPTH) || !defined(PMU50_CNT_W)
#error "build with -DPMU50_SYNC_DEPTH=.. -DPMU50_CNT_W=.. (the Verilog parameters of this build)"
#endif

namespace {

// Interface version: bump when a function or an array order changes.
constexpr uint32_t kAbi = 1;

enum Group { kInputs = 0, kOutputs = 1, kRegisters = 2, kInternals = 3, kResetValues = 4 };

struct Dut {
    VerilatedContext ctx;
    std::unique_ptr<Vpmu50> top;
    Dut() : top(new Vpmu50(&ctx, "pmu50")) {}
};

}  // namespace

/// Interface version (kAbi).
PMU50_DUT_API uint32_t pmu50_dut_abi() { return kAbi; }

/// The structural parameters this library was built for.
PMU50_DUT_API uint32_t pmu50_dut_sync_depth() { return PMU50_SYNC_DEPTH; }
PMU50_DUT_API uint32_t pmu50_dut_cnt_width() { return PMU50_CNT_W; }

/// How many values a group has (0 inputs, 1 outputs, 2 registers, 3 internals, 4 reset values).
PMU50_DUT_API uint32_t pmu50_dut_count(uint32_t group) {
    switch (group) {
    case kInputs: return twin::kInputs;
    case kOutputs: return twin::kOutputs;
    case kRegisters: return twin::kRegisters;
    case kInternals: return twin::kInternals;
    case kResetValues: return twin::kResetValues;
    default: return 0;
    }
}

/// The name of value `i` of a group (the model's signal path), or NULL.
PMU50_DUT_API const char *pmu50_dut_name(uint32_t group, uint32_t i) {
    if (i >= pmu50_dut_count(group)) return nullptr;
    switch (group) {
    case kInputs: return twin::kInputNames[i];
    case kOutputs: return twin::kOutputNames[i];
    case kRegisters: return twin::kRegisterNames[i];
    case kInternals: return twin::kInternalNames[i];
    default: return twin::kResetNames[i];
    }
}

/// A DUT after reset, with the scenario's reset values (pmu50_dut_count(4) values in the
/// order of pmu50_dut_name(4, i)) deposited into the programmable registers.
PMU50_DUT_API void *pmu50_dut_new(const uint64_t *reset) {
    Dut *d = new Dut();
    twin::reset(*d->top, reset);
    return d;
}

PMU50_DUT_API void pmu50_dut_free(void *d) { delete static_cast<Dut *>(d); }

/// The outputs and registers now (after reset, or after the last edge).
PMU50_DUT_API void pmu50_dut_state(void *d, uint64_t *out, uint64_t *regs) {
    Vpmu50 &t = *static_cast<Dut *>(d)->top;
    twin::outputs(t, out);
    twin::registers(t.rootp, regs);
}

/// One tick as a plain Verilator harness runs it, for the speed comparison of `make bench`
/// (benches/regress_speed.rs): the same two evaluations as pmu50_dut_tick, nothing read back
/// but the 23 outputs folded into `acc` (returned), so the work cannot be optimised away.
PMU50_DUT_API uint64_t pmu50_dut_step(void *d, const uint64_t *in, uint64_t acc) {
    Vpmu50 &t = *static_cast<Dut *>(d)->top;
    t.clk = 0;
    twin::set_inputs(t, in);
    t.eval();
    t.clk = 1;
    t.eval();
    uint64_t o[twin::kOutputs];
    twin::outputs(t, o);
    for (uint64_t v : o) acc = (acc ^ v) * 0x100000001b3ull;
    return acc;
}

/// One tick: the inputs of cycle k with clk low (`internals` of the cycle), then rising edge
/// k+1 (`out` and `regs` after it).
PMU50_DUT_API void pmu50_dut_tick(void *d, const uint64_t *in, uint64_t *internals_out, uint64_t *out, uint64_t *regs) {
    Vpmu50 &t = *static_cast<Dut *>(d)->top;
    t.clk = 0;
    twin::set_inputs(t, in);
    t.eval();
    twin::internals(t.rootp, internals_out);
    t.clk = 1;
    t.eval();
    twin::outputs(t, out);
    twin::registers(t.rootp, regs);
}
