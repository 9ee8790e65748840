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
#define PMU50_ERR_NAME  (-5) /* unknown or ambiguous register name */

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

/* Inputs of one clock cycle (held during the cycle, sampled at the rising edge). */
typedef struct pmu50_inputs {
    uint8_t  ig;
    uint8_t  vs2_ok;
    uint8_t  cmp_s;
    uint8_t  cmp_c;
    uint8_t  bus_we;
    uint8_t  bus_addr;
    uint16_t bus_wdata;
} pmu50_inputs;

/* Top-level outputs, in the order of docs/signals.md and of the vector file columns.
 * cnt_s, cnt_c hold CNT_W bits (upper bits 0). */
typedef struct pmu50_outputs {
    uint8_t  sig, vr_hi, vm_en, vs1_en, vs2_en, vp_en, rail_hi;
    uint8_t  st, sr, ps_win, smp;
    uint8_t  cs, cc;
    uint16_t cnt_s, cnt_c;
    uint8_t  cnt_r;
    uint16_t si;
    uint8_t  hist_s, hist_c, diag, quadrant_skip;
    uint16_t bus_rdata;
    uint8_t  bus_err;
} pmu50_outputs;

/* Combinational internals of the cycle that ends at an edge (model VCD scope pmu50.internals,
 * twin scope pmu50.internals). fig17 / fig18: path codes of spec 2.6. */
typedef struct pmu50_internals {
    uint8_t kon, koff, upd, first, chg_s, chg_c, skip_clr;
    uint8_t fig17, fig18;
} pmu50_internals;

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

/* Registers: every flip-flop of the core, in a fixed order (26 entries), named as the model's
 * VCD sub-scopes pmu50.<block>.<name> and as the twin's instances and regs. */
size_t pmu50_reg_count(void);
/* block, name: static strings; width: bits in core `m` (NULL: default configuration). */
int pmu50_reg_info(const pmu50_t *m, size_t index, const char **block, const char **name,
                   uint8_t *width);
int pmu50_reg_get(const pmu50_t *m, size_t index, uint64_t *value);
/* Index (>= 0) of "name", "block.name" or "pmu50.block.name" (a bare name must be unique);
 * negative error code otherwise. */
int pmu50_reg_find(const char *name);
int pmu50_reg_get_by_name(const pmu50_t *m, const char *name, uint64_t *value);

/* Outputs by index (23 entries, column order of the vector files). */
size_t pmu50_output_count(void);
int pmu50_output_info(const pmu50_t *m, size_t index, const char **name, uint8_t *width);
int pmu50_output_get(const pmu50_outputs *o, size_t index, uint64_t *value);

/* Internals by index (9 entries). */
size_t pmu50_internal_count(void);
int pmu50_internal_info(size_t index, const char **name, uint8_t *width);
int pmu50_internal_get(const pmu50_internals *x, size_t index, uint64_t *value);

#ifdef __cplusplus
}
#endif

#endif /* PMU50_H */
