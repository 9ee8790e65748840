/* C smoke test of the C ABI (hdl/ffi/include/pmu50.h), pure C99:
 *   cc -std=c99 -Wall -Wextra -pedantic -Werror -I hdl/ffi/include hdl/ffi/tests/smoke.c \
 *      target/release/libpmu50_ffi.a -lpthread -ldl -lm -o smoke && ./smoke
 * Exercises error handling (NULL, illegal parameters, bad names), a key-on/key-off run and the
 * by-name / by-index accessors. Prints "C ABI smoke test: OK" and exits 0. */
#include <stdio.h>
#include <string.h>

#include "pmu50.h"

#define CHECK(c) do { if (!(c)) { printf("FAIL line %d: %s (%s)\n", __LINE__, #c, pmu50_last_error()); return 1; } } while (0)

int main(void) {
    pmu50_params p;
    CHECK(pmu50_params_default(&p) == PMU50_OK);
    CHECK(p.si_max == 660 && p.sync_depth == 2 && p.cnt_width == 16);
    CHECK(pmu50_params_default(NULL) == PMU50_ERR_NULL);
    CHECK(pmu50_new(NULL) == NULL);

    p.si_min = 700; /* above x */
    CHECK(pmu50_new(&p) == NULL);
    CHECK(strstr(pmu50_last_error(), "min") != NULL);
    CHECK(pmu50_params_validate(&p) == PMU50_ERR_PARAM);
    pmu50_params_default(&p);

    pmu50_t *m = pmu50_new(&p);
    CHECK(m != NULL);
    pmu50_outputs o;
    CHECK(pmu50_peek(m, &o) == PMU50_OK);
    CHECK(o.si == 660 && o.vp_en == 1 && o.sig == 0);

    pmu50_inputs in;
    memset(&in, 0, sizeof in);
    in.ig = 1;
    in.vs2_ok = 1;
    pmu50_internals x;
    unsigned kon = 0;
    for (int k = 0; k < 3; k++) {
        CHECK(pmu50_step_traced(m, &in, &x, &o) == PMU50_OK);
        kon += x.kon;
    }
    CHECK(o.sig == 1 && kon == 1); /* SYNC_DEPTH 2: sig after 2 edges, one kon strobe */
    CHECK(pmu50_tick(m) == 3);

    in.bus_we = 1; in.bus_addr = 0x09; in.bus_wdata = 150; /* T2 := 150 while the key is on */
    CHECK(pmu50_step(m, &in, &o) == PMU50_OK);
    in.bus_we = 0;
    uint64_t v = 0;
    CHECK(pmu50_reg_get_by_name(m, "register_file.t2", &v) == PMU50_OK && v == 150);
    CHECK(pmu50_reg_get_by_name(m, "t2", &v) == PMU50_OK && v == 150);
    CHECK(pmu50_reg_get_by_name(m, "nope", &v) == PMU50_ERR_NAME);
    uint16_t r = 0;
    CHECK(pmu50_bus_read(m, 0x00, &r) == PMU50_OK && r == 0x5050);

    CHECK(pmu50_reg_count() == PMU50_REG_COUNT && pmu50_output_count() == PMU50_OUTPUT_COUNT && pmu50_internal_count() == PMU50_INTERNAL_COUNT);
    const char *block = NULL, *name = NULL;
    uint8_t w = 0;
    CHECK(pmu50_reg_info(m, 18, &block, &name, &w) == PMU50_OK);
    CHECK(strcmp(block, "updown_counter") == 0 && strcmp(name, "cnt_s") == 0 && w == 16);
    CHECK(pmu50_reg_info(m, 26, NULL, NULL, NULL) == PMU50_ERR_RANGE);
    CHECK(pmu50_output_info(m, 16, &name, &w) == PMU50_OK && strcmp(name, "si") == 0 && w == 16);
    CHECK(pmu50_output_get(&o, 0, &v) == PMU50_OK && v == o.sig);

    /* The C mirror structs have the layout the library computes: fields set by index are the
     * named fields. */
    pmu50_outputs t;
    memset(&t, 0, sizeof t);
    for (size_t i = 0; i < PMU50_OUTPUT_COUNT; i++) CHECK(pmu50_output_set(&t, i, i + 1) == PMU50_OK);
    CHECK(t.sig == 1 && t.cc == 13 && t.cnt_s == 14 && t.cnt_c == 15 && t.cnt_r == 16 && t.si == 17);
    CHECK(t.quadrant_skip == 21 && t.bus_rdata == 22 && t.bus_err == 23);
    pmu50_internals ti;
    memset(&ti, 0, sizeof ti);
    for (size_t i = 0; i < PMU50_INTERNAL_COUNT; i++) CHECK(pmu50_internal_set(&ti, i, i + 1) == PMU50_OK);
    CHECK(ti.kon == 1 && ti.skip_clr == 7 && ti.fig17 == 8 && ti.fig18 == 9);
    CHECK(pmu50_output_set(&t, PMU50_OUTPUT_COUNT, 0) == PMU50_ERR_RANGE);

    /* Lockstep compare: the model's own values are equal; one wrong output is reported. */
    CHECK(pmu50_step_traced(m, &in, &x, &o) == PMU50_OK);
    uint64_t regs[PMU50_REG_COUNT];
    for (size_t i = 0; i < PMU50_REG_COUNT; i++) CHECK(pmu50_reg_get(m, i, &regs[i]) == PMU50_OK);
    CHECK(pmu50_check(m, &o, regs, &x) == 0 && strcmp(pmu50_check_report(m), "") == 0);
    o.si ^= 1;
    CHECK(pmu50_check(m, &o, NULL, NULL) == 1);
    CHECK(strstr(pmu50_check_report(m), "MISMATCH tick=5 signal=si expected=0294 got=0295") != NULL);

    CHECK(pmu50_reset(m) == PMU50_OK && pmu50_tick(m) == 0);
    pmu50_params q;
    CHECK(pmu50_get_params(m, &q) == PMU50_OK && q.si_max == p.si_max && q.t2 == p.t2);
    CHECK(pmu50_step(NULL, &in, &o) == PMU50_ERR_NULL);
    CHECK(pmu50_step(m, NULL, &o) == PMU50_ERR_NULL);
    pmu50_free(m);
    pmu50_free(NULL);
    printf("C ABI smoke test: OK (%s)\n", pmu50_version());
    return 0;
}
