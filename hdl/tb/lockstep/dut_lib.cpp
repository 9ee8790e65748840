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
// Built by hdl/scripts/build_lockstep.sh with KIND=lib (one translation unit with the
// Verilator output, -fPIC, the Verilator runtime linked in, every symbol hidden but these).
#include "Vpmu50.h"
#include "Vpmu50___024root.h"
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

const char *const kInputNames[] = {"ig", "vs2_ok", "cmp_s", "cmp_c", "bus_we", "bus_addr", "bus_wdata"};
const char *const kOutputNames[] = {"sig",    "vr_hi", "vm_en", "vs1_en", "vs2_en", "vp_en", "rail_hi", "st",
                                    "sr",     "ps_win", "smp",  "cs",     "cc",     "cnt_s", "cnt_c",   "cnt_r",
                                    "si",     "hist_s", "hist_c", "diag", "quadrant_skip", "bus_rdata", "bus_err"};
const char *const kRegisterNames[] = {
    "action_switching.sync",      "register_file.adaptive",     "register_file.pw",           "register_file.pi",
    "register_file.ps",           "register_file.si_max",       "register_file.si_min",       "register_file.t1",
    "register_file.t2",           "register_file.cth",          "register_file.smp_on",       "register_file.bus_err",
    "register_file.rdata",        "timing_generator.tmr",       "sensor_power_determination.sr", "comparator_latch.cs",
    "comparator_latch.cc",        "comparator_latch.vld",       "updown_counter.cnt_s",       "updown_counter.cnt_c",
    "updown_counter.quadrant_skip", "drive_interval.si",        "drive_interval.hist_s",      "drive_interval.hist_c",
    "drive_interval.cnt_r",       "count_diagnosis.diag"};
const char *const kInternalNames[] = {"kon", "koff", "upd", "first", "chg_s", "chg_c", "skip_clr", "fig17", "fig18"};
// The values deposited right after reset (the build's parameters are the defaults), as the
// HDL parameters of the scenario, plus `si`, which resets to SI_MAX.
const char *const kResetNames[] = {"ADAPTIVE", "PW", "PI", "PS", "SI_MAX", "SI_MIN", "T1", "T2", "CTH", "SMP_ON"};

template <typename T, size_t N> constexpr uint32_t count(const T (&)[N]) { return N; }

struct Dut {
    VerilatedContext ctx;
    std::unique_ptr<Vpmu50> top;
    Dut() : top(new Vpmu50(&ctx, "pmu50")) {}
};

void outputs(const Vpmu50 &t, uint64_t *o) {
    o[0] = t.sig; o[1] = t.vr_hi; o[2] = t.vm_en; o[3] = t.vs1_en; o[4] = t.vs2_en; o[5] = t.vp_en;
    o[6] = t.rail_hi; o[7] = t.st; o[8] = t.sr; o[9] = t.ps_win; o[10] = t.smp; o[11] = t.cs;
    o[12] = t.cc; o[13] = t.cnt_s; o[14] = t.cnt_c; o[15] = t.cnt_r; o[16] = t.si; o[17] = t.hist_s;
    o[18] = t.hist_c; o[19] = t.diag; o[20] = t.quadrant_skip; o[21] = t.bus_rdata; o[22] = t.bus_err;
}

void registers(const Vpmu50___024root *R, uint64_t *r) {
    r[0] = R->pmu50__DOT__action_switching__DOT__sync;
    r[1] = R->pmu50__DOT__register_file__DOT__adaptive;
    r[2] = R->pmu50__DOT__register_file__DOT__pw;
    r[3] = R->pmu50__DOT__register_file__DOT__pi;
    r[4] = R->pmu50__DOT__register_file__DOT__ps;
    r[5] = R->pmu50__DOT__register_file__DOT__si_max;
    r[6] = R->pmu50__DOT__register_file__DOT__si_min;
    r[7] = R->pmu50__DOT__register_file__DOT__t1;
    r[8] = R->pmu50__DOT__register_file__DOT__t2;
    r[9] = R->pmu50__DOT__register_file__DOT__cth;
    r[10] = R->pmu50__DOT__register_file__DOT__smp_on;
    r[11] = R->pmu50__DOT__register_file__DOT__bus_err;
    r[12] = R->pmu50__DOT__register_file__DOT__rdata;
    r[13] = R->pmu50__DOT__timing_generator__DOT__tmr;
    r[14] = R->pmu50__DOT__sensor_power_determination__DOT__sr;
    r[15] = R->pmu50__DOT__comparator_latch__DOT__cs;
    r[16] = R->pmu50__DOT__comparator_latch__DOT__cc;
    r[17] = R->pmu50__DOT__comparator_latch__DOT__vld;
    r[18] = R->pmu50__DOT__updown_counter__DOT__cnt_s;
    r[19] = R->pmu50__DOT__updown_counter__DOT__cnt_c;
    r[20] = R->pmu50__DOT__updown_counter__DOT__quadrant_skip;
    r[21] = R->pmu50__DOT__drive_interval__DOT__si;
    r[22] = R->pmu50__DOT__drive_interval__DOT__hist_s;
    r[23] = R->pmu50__DOT__drive_interval__DOT__hist_c;
    r[24] = R->pmu50__DOT__drive_interval__DOT__cnt_r;
    r[25] = R->pmu50__DOT__count_diagnosis__DOT__diag;
}

void internals(const Vpmu50___024root *R, uint64_t *x) {
    x[0] = R->pmu50__DOT__internals__DOT__kon;
    x[1] = R->pmu50__DOT__internals__DOT__koff;
    x[2] = R->pmu50__DOT__internals__DOT__upd;
    x[3] = R->pmu50__DOT__internals__DOT__first;
    x[4] = R->pmu50__DOT__internals__DOT__chg_s;
    x[5] = R->pmu50__DOT__internals__DOT__chg_c;
    x[6] = R->pmu50__DOT__internals__DOT__skip_clr;
    x[7] = R->pmu50__DOT__internals__DOT__fig17;
    x[8] = R->pmu50__DOT__internals__DOT__fig18;
}

void set_inputs(Vpmu50 &t, const uint64_t *in) {
    t.ig = in[0] & 1; t.vs2_ok = in[1] & 1; t.cmp_s = in[2] & 1; t.cmp_c = in[3] & 1;
    t.bus_we = in[4] & 1; t.bus_addr = static_cast<uint8_t>(in[5]); t.bus_wdata = static_cast<uint16_t>(in[6]);
}

}  // namespace

/// Interface version (kAbi).
PMU50_DUT_API uint32_t pmu50_dut_abi() { return kAbi; }

/// The structural parameters this library was built for.
PMU50_DUT_API uint32_t pmu50_dut_sync_depth() { return PMU50_SYNC_DEPTH; }
PMU50_DUT_API uint32_t pmu50_dut_cnt_width() { return PMU50_CNT_W; }

/// How many values a group has (0 inputs, 1 outputs, 2 registers, 3 internals, 4 reset values).
PMU50_DUT_API uint32_t pmu50_dut_count(uint32_t group) {
    switch (group) {
    case kInputs: return count(kInputNames);
    case kOutputs: return count(kOutputNames);
    case kRegisters: return count(kRegisterNames);
    case kInternals: return count(kInternalNames);
    case kResetValues: return count(kResetNames);
    default: return 0;
    }
}

/// The name of value `i` of a group (the model's signal path), or NULL.
PMU50_DUT_API const char *pmu50_dut_name(uint32_t group, uint32_t i) {
    if (i >= pmu50_dut_count(group)) return nullptr;
    switch (group) {
    case kInputs: return kInputNames[i];
    case kOutputs: return kOutputNames[i];
    case kRegisters: return kRegisterNames[i];
    case kInternals: return kInternalNames[i];
    default: return kResetNames[i];
    }
}

/// A DUT after reset, with the scenario's reset values (pmu50_dut_count(4) values in the
/// order of pmu50_dut_name(4, i)) deposited into the programmable registers.
PMU50_DUT_API void *pmu50_dut_new(const uint64_t *reset) {
    Dut *d = new Dut();
    Vpmu50 &t = *d->top;
    Vpmu50___024root *R = t.rootp;
    const uint64_t zero[7] = {};
    t.clk = 0;
    t.rst_n = 0;
    set_inputs(t, zero);
    t.eval();
    R->pmu50__DOT__register_file__DOT__adaptive = reset[0] ? 1 : 0;
    R->pmu50__DOT__register_file__DOT__pw = reset[1];
    R->pmu50__DOT__register_file__DOT__pi = reset[2];
    R->pmu50__DOT__register_file__DOT__ps = reset[3];
    R->pmu50__DOT__register_file__DOT__si_max = reset[4];
    R->pmu50__DOT__register_file__DOT__si_min = reset[5];
    R->pmu50__DOT__register_file__DOT__t1 = reset[6];
    R->pmu50__DOT__register_file__DOT__t2 = reset[7];
    R->pmu50__DOT__register_file__DOT__cth = reset[8];
    R->pmu50__DOT__register_file__DOT__smp_on = reset[9];
    R->pmu50__DOT__drive_interval__DOT__si = reset[4];
    t.eval();
    t.rst_n = 1;
    t.eval();
    return d;
}

PMU50_DUT_API void pmu50_dut_free(void *d) { delete static_cast<Dut *>(d); }

/// The outputs and registers now (after reset, or after the last edge).
PMU50_DUT_API void pmu50_dut_state(void *d, uint64_t *out, uint64_t *regs) {
    Vpmu50 &t = *static_cast<Dut *>(d)->top;
    outputs(t, out);
    registers(t.rootp, regs);
}

/// One tick as a plain Verilator harness runs it, for the speed comparison of `make bench`
/// (benches/regress_speed.rs): the same two evaluations as pmu50_dut_tick, nothing read back
/// but the 23 outputs folded into `acc` (returned), so the work cannot be optimised away.
PMU50_DUT_API uint64_t pmu50_dut_step(void *d, const uint64_t *in, uint64_t acc) {
    Vpmu50 &t = *static_cast<Dut *>(d)->top;
    t.clk = 0;
    set_inputs(t, in);
    t.eval();
    t.clk = 1;
    t.eval();
    uint64_t o[23];
    outputs(t, o);
    for (uint64_t v : o) acc = (acc ^ v) * 0x100000001b3ull;
    return acc;
}

/// One tick: the inputs of cycle k with clk low (`internals` of the cycle), then rising edge
/// k+1 (`out` and `regs` after it).
PMU50_DUT_API void pmu50_dut_tick(void *d, const uint64_t *in, uint64_t *internals_out, uint64_t *out, uint64_t *regs) {
    Vpmu50 &t = *static_cast<Dut *>(d)->top;
    t.clk = 0;
    set_inputs(t, in);
    t.eval();
    internals(t.rootp, internals_out);
    t.clk = 1;
    t.eval();
    outputs(t, out);
    registers(t.rootp, regs);
}
