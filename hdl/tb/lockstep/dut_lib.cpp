// An RTL under test as a shared library for `pmu50 regress --dut verilator` (verification method
// 2, in process): a thin C interface around one Verilator build of the contract top `pmu50`
// (docs/signals.md) for one set of Verilog parameters (`-G` at build time: the reset values go
// in through the top's parameters, never into its registers). The regression's DUT worker loads
// it (dlopen) and steps it in lockstep with the Rust core (src/regress/lockstep.rs).
//
// Port contract: the library reads and drives the top's ports only. What else it reads is named
// by the header `dut_map.h`, which the regression generates for each build
// (src/regress/dut/verilator.rs) from the contract and from an optional `--map` file:
//   DUT_INPUTS(X)     X(port) per contract input, in the order of the model's signal table
//   DUT_OUTPUTS(X)    X(port) per contract output, in the same order
//   DUT_REGISTERS(X)  X("block.register", value) per mapped register: `value` reads it from the
//                     root class `R` (a member made visible by the build's Verilator
//                     configuration file), `dut_bits(R->member[element], lsb, width)`: the whole
//                     signal, a field of a packed struct, an element of an array, a part
//   DUT_INTERNALS(X)  X("name", value) per mapped internal
//   DUT_PARAMS(X)     X("NAME", value) per Verilog parameter the build set
// With no map, the register and internal lists are empty: nothing of the inside is read.
//
// A build with code coverage (Verilator's `--coverage-line --coverage-toggle`, and
// `--coverage-expr` with a Verilator that has it; VM_COVERAGE=1) counts per DUT handle (each has
// its own VerilatedContext): pmu50_dut_cov_write writes the counts of one handle, from its reset
// on, as a Verilator coverage.dat, a record per instance.
//
// A build with tracing (Verilator's `--trace`, VM_TRACE=1) writes the RTL's own waveform:
// pmu50_dut_vcd_open starts a VCD of one handle, one sample a tick (after the evaluation with the
// clock low: the registers after edge k, the inputs of tick k and what they drive, at time k x
// the clock period), every signal Verilator keeps; pmu50_dut_vcd_close ends it.
//
// A tick is two evaluations, as the Verilog bench's clock: the inputs of cycle k with clk low
// (the mapped internals of the cycle settle), then the rising edge k+1 (outputs, registers).
#include "Vpmu50.h"
#include "Vpmu50___024root.h"
#include "dut_map.h"
#include "verilated.h"
#if VM_COVERAGE
#include "verilated_cov.h"
#endif
#if VM_TRACE
#include "verilated_vcd_c.h"
#endif

#include <cstdint>
#include <memory>
#include <type_traits>

#define PMU50_DUT_API extern "C" __attribute__((visibility("default")))

namespace {

// Interface version: bump when a function or an array order changes.
constexpr uint32_t kAbi = 4;

// Bits lsb..lsb+width-1 (width <= 64) of a value of a Verilator build: an integer of up to 64
// bits, or a VlWide of 32-bit words (a packed struct or vector of more than 64 bits).
template <typename T>
inline uint64_t dut_bits(const T &v, uint32_t lsb, uint32_t width) {
    const uint64_t x = lsb >= 64 ? 0 : static_cast<uint64_t>(v) >> lsb;
    return width >= 64 ? x : x & ((1ull << width) - 1);
}

template <std::size_t N>
inline uint64_t dut_bits(const VlWide<N> &v, uint32_t lsb, uint32_t width) {
    const uint32_t w = lsb / 32, s = lsb % 32;
    unsigned __int128 acc = 0;
    for (uint32_t k = 0; k < 3 && w + k < N; ++k)
        acc |= static_cast<unsigned __int128>(v[w + k]) << (32 * k);
    const uint64_t x = static_cast<uint64_t>(acc >> s);
    return width >= 64 ? x : x & ((1ull << width) - 1);
}

enum Group { kInputGroup = 0, kOutputGroup = 1, kRegisterGroup = 2, kInternalGroup = 3, kParamGroup = 4 };

#define DUT_STR(n) #n,
#define DUT_FIRST(n, m) n,
#define DUT_COUNT(...) +1
constexpr uint32_t kInputs = 0 DUT_INPUTS(DUT_COUNT), kOutputs = 0 DUT_OUTPUTS(DUT_COUNT),
                   kRegisters = 0 DUT_REGISTERS(DUT_COUNT), kInternals = 0 DUT_INTERNALS(DUT_COUNT),
                   kParams = 0 DUT_PARAMS(DUT_COUNT);
const char *const kInputNames[kInputs + 1] = {DUT_INPUTS(DUT_STR) nullptr};
const char *const kOutputNames[kOutputs + 1] = {DUT_OUTPUTS(DUT_STR) nullptr};
const char *const kRegisterNames[kRegisters + 1] = {DUT_REGISTERS(DUT_FIRST) nullptr};
const char *const kInternalNames[kInternals + 1] = {DUT_INTERNALS(DUT_FIRST) nullptr};
const char *const kParamNames[kParams + 1] = {DUT_PARAMS(DUT_FIRST) nullptr};
#define DUT_SECOND(n, v) static_cast<uint64_t>(v),
const uint64_t kParamValues[kParams + 1] = {DUT_PARAMS(DUT_SECOND) 0};

struct Dut {
    VerilatedContext ctx;
    std::unique_ptr<Vpmu50> top;
    // ticks stepped since reset
    uint64_t ticks = 0;
#if VM_TRACE
    std::unique_ptr<VerilatedVcdC> vcd;
    uint64_t ns_per_tick = 1;
#endif
    Dut() : top(make(ctx)) {}
    static Vpmu50 *make(VerilatedContext &c) {
#if VM_TRACE
        c.traceEverOn(true);  // before the model is built
#endif
        return new Vpmu50(&c, "pmu50");
    }
};

inline void set_inputs(Vpmu50 &t, const uint64_t *in) {
    const uint64_t *p = in;
#define DUT_SET(n) t.n = static_cast<std::remove_reference_t<decltype(t.n)>>(*p++);
    DUT_INPUTS(DUT_SET)
#undef DUT_SET
    (void)p;
}

inline void outputs(const Vpmu50 &t, uint64_t *o) {
#define DUT_GET(n) *o++ = static_cast<uint64_t>(t.n);
    DUT_OUTPUTS(DUT_GET)
#undef DUT_GET
    (void)o;
}

inline void registers(const Vpmu50 &t, uint64_t *r) {
    const Vpmu50___024root *R = t.rootp;
#define DUT_GET(n, m) *r++ = (m);
    DUT_REGISTERS(DUT_GET)
#undef DUT_GET
    (void)R;
    (void)r;
}

inline void internals(const Vpmu50 &t, uint64_t *x) {
    const Vpmu50___024root *R = t.rootp;
#define DUT_GET(n, m) *x++ = (m);
    DUT_INTERNALS(DUT_GET)
#undef DUT_GET
    (void)R;
    (void)x;
}

}  // namespace

/// Interface version (kAbi).
PMU50_DUT_API uint32_t pmu50_dut_abi() { return kAbi; }

/// How many values a group has (0 inputs, 1 outputs, 2 registers, 3 internals, 4 parameters).
PMU50_DUT_API uint32_t pmu50_dut_count(uint32_t group) {
    switch (group) {
    case kInputGroup: return kInputs;
    case kOutputGroup: return kOutputs;
    case kRegisterGroup: return kRegisters;
    case kInternalGroup: return kInternals;
    case kParamGroup: return kParams;
    default: return 0;
    }
}

/// The name of value `i` of a group (the model's signal path, or the parameter), or NULL.
PMU50_DUT_API const char *pmu50_dut_name(uint32_t group, uint32_t i) {
    if (i >= pmu50_dut_count(group)) return nullptr;
    switch (group) {
    case kInputGroup: return kInputNames[i];
    case kOutputGroup: return kOutputNames[i];
    case kRegisterGroup: return kRegisterNames[i];
    case kInternalGroup: return kInternalNames[i];
    default: return kParamNames[i];
    }
}

/// The value of parameter `i` this library was built with.
PMU50_DUT_API uint64_t pmu50_dut_param(uint32_t i) { return i < kParams ? kParamValues[i] : 0; }

/// A DUT after power-on reset: inputs 0, clk low, rst_n falling and held low for one
/// evaluation, then released.
PMU50_DUT_API void *pmu50_dut_new() {
    Dut *d = new Dut();
    Vpmu50 &t = *d->top;
    const uint64_t zero[kInputs + 1] = {};
    // a falling edge of rst_n (an asynchronous reset acts on it), held for one evaluation
    t.clk = 0;
    t.rst_n = 1;
    set_inputs(t, zero);
    t.eval();
    t.rst_n = 0;
    t.eval();
    t.rst_n = 1;
    t.eval();
    return d;
}

PMU50_DUT_API void pmu50_dut_free(void *d) { delete static_cast<Dut *>(d); }

/// The outputs and mapped registers now (after reset, or after the last edge).
PMU50_DUT_API void pmu50_dut_state(void *d, uint64_t *out, uint64_t *regs) {
    Vpmu50 &t = *static_cast<Dut *>(d)->top;
    outputs(t, out);
    registers(t, regs);
}

/// One tick as a plain Verilator harness runs it, for the speed comparison of `make bench`
/// (benches/regress_speed.rs): the same two evaluations as pmu50_dut_tick, nothing read back
/// but the outputs folded into `acc` (returned), so the work cannot be optimised away.
PMU50_DUT_API uint64_t pmu50_dut_step(void *d, const uint64_t *in, uint64_t acc) {
    Vpmu50 &t = *static_cast<Dut *>(d)->top;
    t.clk = 0;
    set_inputs(t, in);
    t.eval();
    t.clk = 1;
    t.eval();
    uint64_t o[kOutputs + 1];
    outputs(t, o);
    for (uint32_t k = 0; k < kOutputs; ++k) acc = (acc ^ o[k]) * 0x100000001b3ull;
    return acc;
}

/// One tick: the inputs of cycle k with clk low (mapped `internals` of the cycle), then rising
/// edge k+1 (`out` and mapped `regs` after it).
PMU50_DUT_API void pmu50_dut_tick(void *d, const uint64_t *in, uint64_t *internals_out, uint64_t *out, uint64_t *regs) {
    Dut &u = *static_cast<Dut *>(d);
    Vpmu50 &t = *u.top;
    t.clk = 0;
    set_inputs(t, in);
    t.eval();
    internals(t, internals_out);
#if VM_TRACE
    if (u.vcd) u.vcd->dump(static_cast<uint64_t>(u.ticks * u.ns_per_tick));
#endif
    ++u.ticks;
    t.clk = 1;
    t.eval();
    outputs(t, out);
    registers(t, regs);
}

/// Start the VCD of this handle at `path` (a build with tracing), a tick `ns_per_tick` ns long:
/// 0 started, -1 not a build with tracing.
PMU50_DUT_API int pmu50_dut_vcd_open(void *d, const char *path, uint64_t ns_per_tick) {
#if VM_TRACE
    Dut &u = *static_cast<Dut *>(d);
    u.vcd.reset(new VerilatedVcdC);
    u.top->trace(u.vcd.get(), 99);
    u.vcd->set_time_unit("1ns");
    u.vcd->set_time_resolution("1ns");
    u.vcd->open(path);
    u.ns_per_tick = ns_per_tick ? ns_per_tick : 1;
    return 0;
#else
    (void)d;
    (void)path;
    (void)ns_per_tick;
    return -1;
#endif
}

/// End the VCD of this handle (written and closed).
PMU50_DUT_API void pmu50_dut_vcd_close(void *d) {
#if VM_TRACE
    Dut &u = *static_cast<Dut *>(d);
    if (u.vcd) {
        u.vcd->close();
        u.vcd.reset();
    }
#else
    (void)d;
#endif
}

/// Whether this build counts code coverage (1) or not (0).
PMU50_DUT_API uint32_t pmu50_dut_has_coverage() { return VM_COVERAGE ? 1 : 0; }

/// Write the code coverage of this handle since its reset to `path` (a Verilator coverage.dat):
/// 0 written, -1 not a coverage build.
PMU50_DUT_API int pmu50_dut_cov_write(void *d, const char *path) {
#if VM_COVERAGE
    // a record per instance: a toggle is the changes of one instance's bit (the kit halves each
    // record before it adds the instances of a module), not the sum of two instances' changes
    static_cast<Dut *>(d)->ctx.coveragep()->forcePerInstance(true);
    static_cast<Dut *>(d)->ctx.coveragep()->write(path);
    return 0;
#else
    (void)d;
    (void)path;
    return -1;
#endif
}
