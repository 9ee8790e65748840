/*
 * pmu50.h - C ABI of the PMU 50 digital core reference model (Rust crate pmu50-ffi).
 *
 * The model is cycle-accurate: one pmu50_step() is one rising clock edge of the Verilog twin
 * (hdl/pmu50.v). Outputs are Moore: pmu50_peek() before a step gives the outputs the twin shows
 * during the cycle, pmu50_step() returns the outputs after the edge. Specification:
 * docs/spec.md; port names and widths: docs/signals.md.
 *
 * Build:  cargo build -p pmu50-ffi --release
 *         -> target/release/libpmu50_ffi.a   (link with -lpthread -ldl -lm)
 *         -> target/release/libpmu50_ffi.so
 *
 * Error handling: functions returning int give PMU50_OK (0) or a negative PMU50_ERR_*;
 * pmu50_new() returns NULL on error. The reason is in pmu50_last_error() (thread-local, valid
 * until the next failing call on the same thread). No Rust panic crosses this boundary
 * (PMU50_ERR_PANIC instead); every pointer argument may be NULL (PMU50_ERR_NULL) unless noted.
 * Booleans are uint8_t: any non-zero input is true, outputs are 0 or 1.
 *
 * SystemVerilog DPI-C: the functions taking only scalars and chandle-compatible pointers can be
 * imported directly; for the struct-taking ones write a thin C wrapper or use the C++ testbench
 * of hdl/tb/lockstep as a template.
 */
#ifndef PMU50_H
#define PMU50_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PMU50_OK         0
#define PMU50_ERR_NULL  (-1) /* a required pointer is NULL */
#define PMU50_ERR_PARAM (-2) /* illegal parameter set (spec section 4) */
#define PMU50_ERR_RANGE (-3) /* index out of range */
#define PMU50_ERR_PANIC (-4) /* internal error caught at the boundary (a model bug) */
#define PMU50_ERR_NAME  (-5) /* unknown or ambiguous register or bin name */
#define PMU50_ERR_IO    (-6) /* a file could not be read, written or renamed */
#define PMU50_ERR_TEXT  (-7) /* a string argument is not UTF-8, or empty where a value is needed */
#define PMU50_ERR_COVERAGE (-8) /* a coverage file is corrupt, foreign, or counts a run twice */

/* Configuration: structural parameters and reset values of the programmable registers, in
 * clock ticks. Same names as the `// param` lines of a vector file and the Verilog parameters
 * (SYNC_DEPTH, CNT_W, ADAPTIVE, PW, PI, PS, SI_MAX, SI_MIN, T1, T2, CTH, SMP_ON). */
typedef struct pmu50_params {
    uint8_t  sync_depth; /* SYNC_DEPTH 1..4 */
    uint8_t  cnt_width;  /* CNT_W 2..16 */
    uint8_t  adaptive;   /* ADAPTIVE: CTRL bit 0 */
    uint8_t  cth;        /* CTH 1..255 */
    uint16_t pw;         /* PW */
    uint16_t pi;         /* PI */
    uint16_t ps;         /* PS (not 0) */
    uint16_t si_max;     /* SI_MAX, the maximum interval x (not 0) */
    uint16_t si_min;     /* SI_MIN (not 0, <= si_max) */
    uint16_t t1;         /* T1 (not 0) */
    uint16_t t2;         /* T2 (not 0) */
    uint16_t smp_on;     /* SMP_ON (not 0) */
} pmu50_params;

/* BEGIN GENERATED from rtl_model/core/src/signals.rs; do not edit (hdl/ffi/tests/header.rs) */
#define PMU50_INPUT_COUNT    7
#define PMU50_OUTPUT_COUNT   23
#define PMU50_REG_COUNT      26
#define PMU50_INTERNAL_COUNT 9

/* Inputs of one clock cycle (held during the cycle, sampled at the rising edge). */
typedef struct pmu50_inputs {
    uint8_t  ig;             /* [1] ignition key signal IG */
    uint8_t  vs2_ok;         /* [1] Vs2 power-good from the analog rail monitor */
    uint8_t  cmp_s;          /* [1] raw decision of comparator 58a (sin2 >= Vr) */
    uint8_t  cmp_c;          /* [1] raw decision of comparator 58b (cos2 >= Vr) */
    uint8_t  bus_we;         /* [1] register write strobe */
    uint8_t  bus_addr;       /* [8] register address */
    uint16_t bus_wdata;      /* [16] register write data */
} pmu50_inputs;

/* Top-level outputs, in the order of docs/signals.md and of the vector file columns. A
 * field wider than its signal holds it in the low bits (upper bits 0). */
typedef struct pmu50_outputs {
    uint8_t  sig;            /* [1] operation switching signal Sig */
    uint8_t  vr_hi;          /* [1] regulator 51: 6 V (1) / 4 V (0) */
    uint8_t  vm_en;          /* [1] power source Vm on (unit 52) */
    uint8_t  vs1_en;         /* [1] first sensor power Vs1 on (unit 53) */
    uint8_t  vs2_en;         /* [1] second sensor power Vs2 on (unit 54) */
    uint8_t  vp_en;          /* [1] internal power Vp on (always 1) */
    uint8_t  rail_hi;        /* [1] Vs2 and Vp at Vcc1 (1) / Vcc2 (0) */
    uint8_t  st;             /* [1] timing signal St */
    uint8_t  sr;             /* [1] activation signal Sr */
    uint8_t  ps_win;         /* [1] inside the sampling period Ps */
    uint8_t  smp;            /* [1] sampling strobe */
    uint8_t  cs;             /* [1] sign signal Cs (latched) */
    uint8_t  cc;             /* [1] sign signal Cc (latched) */
    uint16_t cnt_s;          /* [CNT_W] sine count value CNTs */
    uint16_t cnt_c;          /* [CNT_W] cosine count value CNTc */
    uint8_t  cnt_r;          /* [8] power supply count CNTr */
    uint16_t si;             /* [16] drive interval instruction Si, in ticks */
    uint8_t  hist_s;         /* [1] change history of Cs */
    uint8_t  hist_c;         /* [1] change history of Cc */
    uint8_t  diag;           /* [1] count diagnosis */
    uint8_t  quadrant_skip;  /* [1] sticky: both signs changed in one sample */
    uint16_t bus_rdata;      /* [16] registered read data */
    uint8_t  bus_err;        /* [1] sticky: a write was refused */
} pmu50_outputs;

/* Combinational internals of the cycle that ends at an edge (model VCD scope pmu50.internals,
 * twin scope pmu50.internals). fig17 / fig18: path codes of spec 2.6. */
typedef struct pmu50_internals {
    uint8_t  kon;            /* [1] `sig` rises at this edge (key on) */
    uint8_t  koff;           /* [1] `sig` falls at this edge (key off) */
    uint8_t  upd;            /* [1] a sample is taken at this edge (`smp` & `sr`) */
    uint8_t  first;          /* [1] this sample is the first since reset */
    uint8_t  chg_s;          /* [1] `cs` changes at this edge */
    uint8_t  chg_c;          /* [1] `cc` changes at this edge */
    uint8_t  skip_clr;       /* [1] write-1-to-clear strobe of STATUS.quadrant_skip */
    uint8_t  fig17;          /* [3] FIG. 17 path taken at this edge (spec 2.6) */
    uint8_t  fig18;          /* [3] FIG. 18 path taken at this edge (spec 2.6) */
} pmu50_internals;

/* Registers by index (pmu50_reg_info, pmu50_reg_get, the rtl_regs array of pmu50_check):
 *   0  action_switching.sync                  SYNC_DEPTH
 *   1  register_file.adaptive                 1
 *   2  register_file.pw                       16
 *   3  register_file.pi                       16
 *   4  register_file.ps                       16
 *   5  register_file.si_max                   16
 *   6  register_file.si_min                   16
 *   7  register_file.t1                       16
 *   8  register_file.t2                       16
 *   9  register_file.cth                      8
 *  10  register_file.smp_on                   16
 *  11  register_file.bus_err                  1
 *  12  register_file.rdata                    16
 *  13  timing_generator.tmr                   16
 *  14  sensor_power_determination.sr          1
 *  15  comparator_latch.cs                    1
 *  16  comparator_latch.cc                    1
 *  17  comparator_latch.vld                   1
 *  18  updown_counter.cnt_s                   CNT_W
 *  19  updown_counter.cnt_c                   CNT_W
 *  20  updown_counter.quadrant_skip           1
 *  21  drive_interval.si                      16
 *  22  drive_interval.hist_s                  1
 *  23  drive_interval.hist_c                  1
 *  24  drive_interval.cnt_r                   8
 *  25  count_diagnosis.diag                   1
 */
/* END GENERATED */

typedef struct pmu50_t pmu50_t; /* opaque */

/* Library version string (static). */
const char *pmu50_version(void);
/* Message of the last failed call on this thread ("" if none). */
const char *pmu50_last_error(void);

/* Default parameters (the patent's values at a 10 us clock). */
int pmu50_params_default(pmu50_params *out);
/* PMU50_OK if legal, else PMU50_ERR_PARAM and the violated rule in pmu50_last_error(). */
int pmu50_params_validate(const pmu50_params *p);

/* New core at power-on reset; NULL if `p` is NULL or illegal (see pmu50_last_error()). */
pmu50_t *pmu50_new(const pmu50_params *p);
/* Free a core; NULL is ignored. */
void pmu50_free(pmu50_t *m);
/* Back to power-on reset with the same parameters; tick count 0. */
int pmu50_reset(pmu50_t *m);
/* The parameters the core was created with. */
int pmu50_get_params(const pmu50_t *m, pmu50_params *out);

/* One rising edge with inputs `i`. `after` (may be NULL): outputs after the edge. */
int pmu50_step(pmu50_t *m, const pmu50_inputs *i, pmu50_outputs *after);
/* As pmu50_step; `internals` (may be NULL): internals of the cycle that ends at this edge. */
int pmu50_step_traced(pmu50_t *m, const pmu50_inputs *i, pmu50_internals *internals,
                      pmu50_outputs *after);
/* Outputs of the current cycle (after the last edge; reset values before the first). */
int pmu50_peek(const pmu50_t *m, pmu50_outputs *out);
/* Number of edges since reset (0 for NULL). */
uint64_t pmu50_tick(const pmu50_t *m);
/* Register file read mux at `addr` in the current cycle (bus_rdata one edge later). */
int pmu50_bus_read(const pmu50_t *m, uint8_t addr, uint16_t *out);

/* Registers: every flip-flop of the core, in a fixed order (PMU50_REG_COUNT entries, listed
 * above), named as the model's VCD sub-scopes pmu50.<block>.<name> and as the twin's instances
 * and regs. */
size_t pmu50_reg_count(void);
/* block, name: static strings; width: bits in core `m` (NULL: default configuration). */
int pmu50_reg_info(const pmu50_t *m, size_t index, const char **block, const char **name,
                   uint8_t *width);
int pmu50_reg_get(const pmu50_t *m, size_t index, uint64_t *value);
/* Index (>= 0) of "name", "block.name" or "pmu50.block.name" (a bare name must be unique);
 * negative error code otherwise. */
int pmu50_reg_find(const char *name);
int pmu50_reg_get_by_name(const pmu50_t *m, const char *name, uint64_t *value);

/* Outputs by index (PMU50_OUTPUT_COUNT entries, column order of the vector files). */
size_t pmu50_output_count(void);
int pmu50_output_info(const pmu50_t *m, size_t index, const char **name, uint8_t *width);
int pmu50_output_get(const pmu50_outputs *o, size_t index, uint64_t *value);
/* Set output `index` (low bits of `value`): fill a struct from an RTL simulator by index. */
int pmu50_output_set(pmu50_outputs *o, size_t index, uint64_t value);

/* Internals by index (PMU50_INTERNAL_COUNT entries). */
size_t pmu50_internal_count(void);
int pmu50_internal_info(size_t index, const char **name, uint8_t *width);
int pmu50_internal_get(const pmu50_internals *x, size_t index, uint64_t *value);
int pmu50_internal_set(pmu50_internals *x, size_t index, uint64_t value);

/* Lockstep compare (verification method 2), the one comparison every testbench uses: the RTL's
 * values against the model's. Each set is optional (NULL: not compared):
 *   rtl_outputs    the RTL's outputs after the last edge (tick = pmu50_tick(m));
 *   rtl_regs       PMU50_REG_COUNT register values after the last edge, in register index order;
 *   rtl_internals  the RTL's internals of the cycle that ended at the last edge, sampled before
 *                  that edge (tick = pmu50_tick(m) - 1; needs a pmu50_step/_traced first).
 * Returns the number of differing signals (0: equal) or a negative PMU50_ERR_*. The report is in
 * pmu50_check_report(m), one line per difference, in table order:
 *   MISMATCH tick=<k> signal=<path> expected=<model, hex> got=<rtl, hex>
 * with <path> as below pmu50 in the VCD (si, drive_interval.si, internals.fig17). */
int pmu50_check(pmu50_t *m, const pmu50_outputs *rtl_outputs, const uint64_t *rtl_regs,
                const pmu50_internals *rtl_internals);
/* Report of the last pmu50_check on `m` ("" when equal); valid until the next check on `m`. */
const char *pmu50_check_report(const pmu50_t *m);

/* Functional coverage (docs/coverage-abi.md, docs/verification.md): the model's covergroups,
 * sampled at every edge of a core, written as coverage.json (the merge format of `pmu50 merge`).
 * Sampling is done by stepping the core through the coverage handle: pmu50_coverage_step is
 * pmu50_step plus the sample, the same numbers as the Rust and Python samplers. */
typedef struct pmu50_coverage_t pmu50_coverage_t; /* opaque */

/* Empty coverage for a core of parameters `p` at clock period `clock_ns` (the configuration is
 * sampled now); NULL if `p` is NULL or illegal (see pmu50_last_error()). */
pmu50_coverage_t *pmu50_coverage_new(const pmu50_params *p, uint64_t clock_ns);
/* Free a coverage handle; NULL is ignored. */
void pmu50_coverage_free(pmu50_coverage_t *c);
/* One rising edge of core `m` with inputs `i`, sampled into `c`: pmu50_step / pmu50_step_traced
 * plus the sample (so pmu50_check of internals works after it). PMU50_ERR_PARAM if `m` has
 * another SYNC_DEPTH or CNT_W than `c` was made for. */
int pmu50_coverage_step(pmu50_coverage_t *c, pmu50_t *m, const pmu50_inputs *i, pmu50_outputs *after);
int pmu50_coverage_step_traced(pmu50_coverage_t *c, pmu50_t *m, const pmu50_inputs *i,
                               pmu50_internals *internals, pmu50_outputs *after);
/* Edges sampled into `c` (0 for NULL). */
uint64_t pmu50_coverage_edges(const pmu50_coverage_t *c);

/* Bins of the model, by index (points first, then crosses; the order of coverage.json). */
size_t pmu50_coverage_bin_count(void);
/* The model's identity (static), carried by every coverage file. */
const char *pmu50_coverage_model(void);
/* name: static "group.point.bin" or "cross.<name>.<a>*<b>"; is_cross: 0 or 1; unreachable:
 * static reason why the bin can never be hit, or NULL. Out pointers may be NULL. */
int pmu50_coverage_bin_info(size_t index, const char **name, uint8_t *is_cross,
                            const char **unreachable);
/* Index (>= 0) of the bin `name`, or PMU50_ERR_NAME / PMU50_ERR_TEXT / PMU50_ERR_NULL. */
int pmu50_coverage_find(const char *name);
int pmu50_coverage_hits(const pmu50_coverage_t *c, size_t index, uint64_t *hits);
/* Bins hit at least once and bins that can be hit (out pointers may be NULL). */
int pmu50_coverage_closure(const pmu50_coverage_t *c, size_t *hit, size_t *reachable);

/* Write coverage.json of this run to `path` (temporary file renamed into place): the hits of
 * `c` and one run `run_id` (unique across everything merged, e.g. "dpi/fig15a/1") with
 * `verdict` ("pass", "fail", ...). PMU50_ERR_IO, PMU50_ERR_TEXT (not UTF-8, empty). */
int pmu50_coverage_write(const pmu50_coverage_t *c, const char *path, const char *run_id,
                         const char *verdict);
/* Merge `n` coverage files into `out`, as `pmu50 merge`: PMU50_ERR_COVERAGE (corrupt, foreign,
 * a run counted twice) or PMU50_ERR_IO with the file in pmu50_last_error(); nothing is written
 * then. */
int pmu50_coverage_merge(const char *const *paths, size_t n, const char *out);

#ifdef __cplusplus
}
#endif

#endif /* PMU50_H */
