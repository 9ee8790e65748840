/*
 * pmu50_dpi.c - SystemVerilog DPI-C shim over the C ABI of the PMU 50 reference model
 * (hdl/ffi/include/pmu50.h), with scalar arguments only, so that any SystemVerilog simulator can
 * import it (see tb_lockstep_dpi.sv for the import declarations and a lockstep testbench).
 *
 * Build: compile this file with -I hdl/ffi/include and link target/release/libpmu50_ffi.a
 * (-lpthread -ldl -lm), or the shared library libpmu50_ffi.so.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "pmu50.h"

/* C linkage also when the simulator compiles this file as C++ (Verilator does). */
#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    pmu50_t *m;
    pmu50_coverage_t *cov;   /* functional coverage sampled at every step, or NULL */
    pmu50_outputs after;     /* outputs after the last step (reset values before the first) */
    pmu50_internals last;    /* internals of the cycle that ended at the last step */
} pmu50_dpi_t;

void *pmu50_dpi_new(int sync_depth, int cnt_width, int adaptive, int pw, int pi, int ps, int si_max,
                    int si_min, int t1, int t2, int cth, int smp_on) {
    pmu50_params p;
    pmu50_params_default(&p);
    p.sync_depth = (uint8_t)sync_depth;
    p.cnt_width = (uint8_t)cnt_width;
    p.adaptive = (uint8_t)(adaptive != 0);
    p.pw = (uint16_t)pw;
    p.pi = (uint16_t)pi;
    p.ps = (uint16_t)ps;
    p.si_max = (uint16_t)si_max;
    p.si_min = (uint16_t)si_min;
    p.t1 = (uint16_t)t1;
    p.t2 = (uint16_t)t2;
    p.cth = (uint8_t)cth;
    p.smp_on = (uint16_t)smp_on;
    pmu50_t *m = pmu50_new(&p);
    if (!m) return NULL;
    pmu50_dpi_t *h = (pmu50_dpi_t *)calloc(1, sizeof *h);
    if (!h) {
        pmu50_free(m);
        return NULL;
    }
    h->m = m;
    pmu50_peek(m, &h->after);
    return h;
}

const char *pmu50_dpi_last_error(void) { return pmu50_last_error(); }

void pmu50_dpi_free(void *handle) {
    pmu50_dpi_t *h = (pmu50_dpi_t *)handle;
    if (!h) return;
    pmu50_coverage_free(h->cov);
    pmu50_free(h->m);
    free(h);
}

/* Sample the functional coverage model at every following step (clock period `clock_ns`).
 * 0 = ok, negative = error (pmu50_dpi_last_error). */
int pmu50_dpi_coverage_on(void *handle, long long clock_ns) {
    pmu50_dpi_t *h = (pmu50_dpi_t *)handle;
    pmu50_params p;
    if (!h) return PMU50_ERR_NULL;
    if (h->cov) return 0;
    int rc = pmu50_get_params(h->m, &p);
    if (rc != PMU50_OK) return rc;
    h->cov = pmu50_coverage_new(&p, (uint64_t)clock_ns);
    return h->cov ? 0 : PMU50_ERR_PARAM;
}

/* Write the coverage sampled so far as coverage.json (`run_id` unique across everything merged,
 * `verdict` "pass" or "fail"). 0 = ok, negative = error (pmu50_dpi_last_error). */
int pmu50_dpi_coverage_write(void *handle, const char *path, const char *run_id, const char *verdict) {
    pmu50_dpi_t *h = (pmu50_dpi_t *)handle;
    if (!h) return PMU50_ERR_NULL;
    return pmu50_coverage_write(h->cov, path, run_id, verdict);
}

/* One rising edge with these inputs. 0 = ok, negative = error (pmu50_dpi_last_error). */
int pmu50_dpi_step(void *handle, int ig, int vs2_ok, int cmp_s, int cmp_c, int bus_we, int bus_addr,
                   int bus_wdata) {
    pmu50_dpi_t *h = (pmu50_dpi_t *)handle;
    if (!h) return PMU50_ERR_NULL;
    pmu50_inputs in;
    in.ig = (uint8_t)(ig & 1);
    in.vs2_ok = (uint8_t)(vs2_ok & 1);
    in.cmp_s = (uint8_t)(cmp_s & 1);
    in.cmp_c = (uint8_t)(cmp_c & 1);
    in.bus_we = (uint8_t)(bus_we & 1);
    in.bus_addr = (uint8_t)bus_addr;
    in.bus_wdata = (uint16_t)bus_wdata;
    if (h->cov) return pmu50_coverage_step_traced(h->cov, h->m, &in, &h->last, &h->after);
    return pmu50_step_traced(h->m, &in, &h->last, &h->after);
}

/* Output `index` (column order of the vector files) after the last step; -1 on error. */
long long pmu50_dpi_output(void *handle, int index) {
    pmu50_dpi_t *h = (pmu50_dpi_t *)handle;
    uint64_t v = 0;
    if (!h || index < 0 || pmu50_output_get(&h->after, (size_t)index, &v) != PMU50_OK) return -1;
    return (long long)v;
}

/* Internal signal `index` of the cycle that ended at the last step; -1 on error. */
long long pmu50_dpi_internal(void *handle, int index) {
    pmu50_dpi_t *h = (pmu50_dpi_t *)handle;
    uint64_t v = 0;
    if (!h || index < 0 || pmu50_internal_get(&h->last, (size_t)index, &v) != PMU50_OK) return -1;
    return (long long)v;
}

/* Register by name ("drive_interval.si", "si", ...); -1 on error. */
long long pmu50_dpi_reg(void *handle, const char *name) {
    pmu50_dpi_t *h = (pmu50_dpi_t *)handle;
    uint64_t v = 0;
    if (!h || pmu50_reg_get_by_name(h->m, name, &v) != PMU50_OK) return -1;
    return (long long)v;
}

/* 0 when the bench's array sizes are the library's counts, else -1 (message in
 * pmu50_dpi_last_error is not set: the caller reports). */
int pmu50_dpi_check_sizes(int n_outputs, int n_regs, int n_internals) {
    return (n_outputs == PMU50_OUTPUT_COUNT && n_regs == PMU50_REG_COUNT && n_internals == PMU50_INTERNAL_COUNT) ? 0 : -1;
}

/* Lockstep compare of the state after the last step (pmu50_check): `outputs` has
 * PMU50_OUTPUT_COUNT values in output index order, `regs` PMU50_REG_COUNT values in register
 * index order (ignored when with_regs = 0). Returns the number of differing signals or a negative
 * error; the MISMATCH lines are in pmu50_dpi_check_report. */
int pmu50_dpi_check_state(void *handle, const long long *outputs, const long long *regs, int with_regs) {
    pmu50_dpi_t *h = (pmu50_dpi_t *)handle;
    if (!h || !outputs || (with_regs && !regs)) return PMU50_ERR_NULL;
    pmu50_outputs o;
    memset(&o, 0, sizeof o);
    for (size_t i = 0; i < PMU50_OUTPUT_COUNT; i++) pmu50_output_set(&o, i, (uint64_t)outputs[i]);
    uint64_t r[PMU50_REG_COUNT];
    if (with_regs)
        for (size_t i = 0; i < PMU50_REG_COUNT; i++) r[i] = (uint64_t)regs[i];
    return pmu50_check(h->m, &o, with_regs ? r : NULL, NULL);
}

/* Lockstep compare of the internals of the cycle that ended at the last step (sampled before
 * that edge): PMU50_INTERNAL_COUNT values in internal index order. */
int pmu50_dpi_check_internals(void *handle, const long long *internals) {
    pmu50_dpi_t *h = (pmu50_dpi_t *)handle;
    if (!h || !internals) return PMU50_ERR_NULL;
    pmu50_internals x;
    memset(&x, 0, sizeof x);
    for (size_t i = 0; i < PMU50_INTERNAL_COUNT; i++) pmu50_internal_set(&x, i, (uint64_t)internals[i]);
    return pmu50_check(h->m, NULL, NULL, &x);
}

/* MISMATCH lines of the last check ("" when equal). */
const char *pmu50_dpi_check_report(void *handle) {
    pmu50_dpi_t *h = (pmu50_dpi_t *)handle;
    return h ? pmu50_check_report(h->m) : "";
}

const char *pmu50_dpi_output_name(int index) {
    const char *n = "?";
    if (index < 0 || pmu50_output_info(NULL, (size_t)index, &n, NULL) != PMU50_OK) return "?";
    return n;
}

const char *pmu50_dpi_internal_name(int index) {
    const char *n = "?";
    if (index < 0 || pmu50_internal_info((size_t)index, &n, NULL) != PMU50_OK) return "?";
    return n;
}

#ifdef __cplusplus
}
#endif
