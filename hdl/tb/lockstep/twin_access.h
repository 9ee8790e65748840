// The Verilator model of the contract top `pmu50` (docs/signals.md) as arrays of values in the
// order of the model's signal table: the one place that knows the twin's hierarchical names,
// shared by the lockstep testbench (lockstep.cpp) and the RTL library of `pmu50 regress --dut
// verilator` (dut_lib.cpp). lockstep.vlt makes these registers and internals visible
// (public_flat_rw / public_flat_rd), without pragmas in the RTL. For an RTL with other internal
// names, edit the tables of this file.
#pragma once

#include "Vpmu50.h"
#include "Vpmu50___024root.h"

#include <cstdint>

namespace twin {

constexpr int kInputs = 7, kOutputs = 23, kRegisters = 26, kInternals = 9, kResetValues = 10;

// Names in the order of the model's signal table (signals::INPUTS, OUTPUTS, REGISTERS with their
// block scope, INTERNALS); the consumers check them against the model's at start.
const char *const kInputNames[kInputs] = {"ig", "vs2_ok", "cmp_s", "cmp_c", "bus_we", "bus_addr", "bus_wdata"};
const char *const kOutputNames[kOutputs] = {"sig", "vr_hi", "vm_en", "vs1_en", "vs2_en", "vp_en", "rail_hi", "st",
                                            "sr", "ps_win", "smp", "cs", "cc", "cnt_s", "cnt_c", "cnt_r",
                                            "si", "hist_s", "hist_c", "diag", "quadrant_skip", "bus_rdata", "bus_err"};
const char *const kRegisterNames[kRegisters] = {
    "action_switching.sync", "register_file.adaptive", "register_file.pw", "register_file.pi",
    "register_file.ps", "register_file.si_max", "register_file.si_min", "register_file.t1",
    "register_file.t2", "register_file.cth", "register_file.smp_on", "register_file.bus_err",
    "register_file.rdata", "timing_generator.tmr", "sensor_power_determination.sr", "comparator_latch.cs",
    "comparator_latch.cc", "comparator_latch.vld", "updown_counter.cnt_s", "updown_counter.cnt_c",
    "updown_counter.quadrant_skip", "drive_interval.si", "drive_interval.hist_s", "drive_interval.hist_c",
    "drive_interval.cnt_r", "count_diagnosis.diag"};
const char *const kInternalNames[kInternals] = {"kon", "koff", "upd", "first", "chg_s", "chg_c", "skip_clr", "fig17", "fig18"};
// The values deposited right after reset (a build's parameters are the defaults), named by the
// HDL parameters of the scenario; `si` resets to SI_MAX.
const char *const kResetNames[kResetValues] = {"ADAPTIVE", "PW", "PI", "PS", "SI_MAX", "SI_MIN", "T1", "T2", "CTH", "SMP_ON"};

inline void outputs(const Vpmu50 &t, uint64_t *o) {
    o[0] = t.sig; o[1] = t.vr_hi; o[2] = t.vm_en; o[3] = t.vs1_en; o[4] = t.vs2_en; o[5] = t.vp_en;
    o[6] = t.rail_hi; o[7] = t.st; o[8] = t.sr; o[9] = t.ps_win; o[10] = t.smp; o[11] = t.cs;
    o[12] = t.cc; o[13] = t.cnt_s; o[14] = t.cnt_c; o[15] = t.cnt_r; o[16] = t.si; o[17] = t.hist_s;
    o[18] = t.hist_c; o[19] = t.diag; o[20] = t.quadrant_skip; o[21] = t.bus_rdata; o[22] = t.bus_err;
}

inline void registers(const Vpmu50___024root *R, uint64_t *r) {
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

inline void internals(const Vpmu50___024root *R, uint64_t *x) {
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

inline void set_inputs(Vpmu50 &t, const uint64_t *in) {
    t.ig = in[0] & 1; t.vs2_ok = in[1] & 1; t.cmp_s = in[2] & 1; t.cmp_c = in[3] & 1;
    t.bus_we = in[4] & 1; t.bus_addr = static_cast<uint8_t>(in[5]); t.bus_wdata = static_cast<uint16_t>(in[6]);
}

// Power-on reset with the scenario's reset values (kResetNames order) deposited into the
// programmable registers, then reset released; the inputs are all 0, clk low.
inline void reset(Vpmu50 &t, const uint64_t *v) {
    Vpmu50___024root *R = t.rootp;
    const uint64_t zero[kInputs] = {};
    t.clk = 0;
    t.rst_n = 0;
    set_inputs(t, zero);
    t.eval();
    R->pmu50__DOT__register_file__DOT__adaptive = v[0] ? 1 : 0;
    R->pmu50__DOT__register_file__DOT__pw = v[1];
    R->pmu50__DOT__register_file__DOT__pi = v[2];
    R->pmu50__DOT__register_file__DOT__ps = v[3];
    R->pmu50__DOT__register_file__DOT__si_max = v[4];
    R->pmu50__DOT__register_file__DOT__si_min = v[5];
    R->pmu50__DOT__register_file__DOT__t1 = v[6];
    R->pmu50__DOT__register_file__DOT__t2 = v[7];
    R->pmu50__DOT__register_file__DOT__cth = v[8];
    R->pmu50__DOT__register_file__DOT__smp_on = v[9];
    R->pmu50__DOT__drive_interval__DOT__si = v[4];
    t.eval();
    t.rst_n = 1;
    t.eval();
}

}  // namespace twin
