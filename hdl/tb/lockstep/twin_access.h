// The Verilator model of the contract top `pmu50` (docs/signals.md) as arrays of values in the
// order of the model's signal table: the one place that knows the twin's hierarchical names,
// shared by the lockstep testbench (lockstep.cpp) and the RTL library of `pmu50 regress --dut
// verilator` (dut_lib.cpp). lockstep.vlt makes these registers and internals visible
// (public_flat_rw / public_flat_rd), without pragmas in the RTL. For an RTL with other internal
// names, edit the tables of this file (TWIN_REGISTERS, TWIN_INTERNALS).
#pragma once

#include "Vpmu50.h"
#include "Vpmu50___024root.h"

#include <cstdint>

namespace twin {

// The tables, one line per signal, in the order of the model's signal table (signals::INPUTS,
// OUTPUTS, REGISTERS with their block scope, INTERNALS); the consumers check the names against
// the model's at start. X(name) for a port of the top; X(block, name) for a register, the
// instance `block` of pmu50.v; X(name) for an internal of the instance `internals`.
#define TWIN_INPUTS(X) X(ig) X(vs2_ok) X(cmp_s) X(cmp_c) X(bus_we) X(bus_addr) X(bus_wdata)
#define TWIN_OUTPUTS(X)                                                                          \
    X(sig) X(vr_hi) X(vm_en) X(vs1_en) X(vs2_en) X(vp_en) X(rail_hi) X(st) X(sr) X(ps_win)      \
    X(smp) X(cs) X(cc) X(cnt_s) X(cnt_c) X(cnt_r) X(si) X(hist_s) X(hist_c) X(diag)             \
    X(quadrant_skip) X(bus_rdata) X(bus_err)
#define TWIN_REGISTERS(X)                                                                        \
    X(action_switching, sync)                                                                    \
    X(register_file, adaptive) X(register_file, pw) X(register_file, pi) X(register_file, ps)   \
    X(register_file, si_max) X(register_file, si_min) X(register_file, t1) X(register_file, t2) \
    X(register_file, cth) X(register_file, smp_on) X(register_file, bus_err)                    \
    X(register_file, rdata)                                                                      \
    X(timing_generator, tmr)                                                                     \
    X(sensor_power_determination, sr)                                                            \
    X(comparator_latch, cs) X(comparator_latch, cc) X(comparator_latch, vld)                    \
    X(updown_counter, cnt_s) X(updown_counter, cnt_c) X(updown_counter, quadrant_skip)          \
    X(drive_interval, si) X(drive_interval, hist_s) X(drive_interval, hist_c)                   \
    X(drive_interval, cnt_r)                                                                     \
    X(count_diagnosis, diag)
#define TWIN_INTERNALS(X) X(kon) X(koff) X(upd) X(first) X(chg_s) X(chg_c) X(skip_clr) X(fig17) X(fig18)
// The values deposited right after reset (a build's parameters are the defaults): X(HDL
// parameter, register of register_file = field of pmu50_params); `si` resets to SI_MAX.
#define TWIN_RESET_VALUES(X)                                                                     \
    X(ADAPTIVE, adaptive) X(PW, pw) X(PI, pi) X(PS, ps) X(SI_MAX, si_max) X(SI_MIN, si_min)     \
    X(T1, t1) X(T2, t2) X(CTH, cth) X(SMP_ON, smp_on)

#define TWIN_NAME(n) #n,
#define TWIN_SCOPED_NAME(b, n) #b "." #n,
#define TWIN_FIRST_NAME(n, f) #n,
#define TWIN_COUNT(...) +1
constexpr int kInputs = 0 TWIN_INPUTS(TWIN_COUNT), kOutputs = 0 TWIN_OUTPUTS(TWIN_COUNT),
              kRegisters = 0 TWIN_REGISTERS(TWIN_COUNT), kInternals = 0 TWIN_INTERNALS(TWIN_COUNT),
              kResetValues = 0 TWIN_RESET_VALUES(TWIN_COUNT);

const char *const kInputNames[kInputs] = {TWIN_INPUTS(TWIN_NAME)};
const char *const kOutputNames[kOutputs] = {TWIN_OUTPUTS(TWIN_NAME)};
const char *const kRegisterNames[kRegisters] = {TWIN_REGISTERS(TWIN_SCOPED_NAME)};
const char *const kInternalNames[kInternals] = {TWIN_INTERNALS(TWIN_NAME)};
const char *const kResetNames[kResetValues] = {TWIN_RESET_VALUES(TWIN_FIRST_NAME)};

inline void outputs(const Vpmu50 &t, uint64_t *o) {
#define TWIN_GET(n) *o++ = t.n;
    TWIN_OUTPUTS(TWIN_GET)
#undef TWIN_GET
}

inline void registers(const Vpmu50___024root *R, uint64_t *r) {
#define TWIN_GET(b, n) *r++ = R->pmu50__DOT__##b##__DOT__##n;
    TWIN_REGISTERS(TWIN_GET)
#undef TWIN_GET
}

inline void internals(const Vpmu50___024root *R, uint64_t *x) {
#define TWIN_GET(n) *x++ = R->pmu50__DOT__internals__DOT__##n;
    TWIN_INTERNALS(TWIN_GET)
#undef TWIN_GET
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
    const uint64_t *p = v;
#define TWIN_DEPOSIT(P, n) R->pmu50__DOT__register_file__DOT__##n = *p++;
    TWIN_RESET_VALUES(TWIN_DEPOSIT)
#undef TWIN_DEPOSIT
    R->pmu50__DOT__register_file__DOT__adaptive = v[0] ? 1 : 0;
    R->pmu50__DOT__drive_interval__DOT__si = v[4];
    t.eval();
    t.rst_n = 1;
    t.eval();
}

}  // namespace twin
