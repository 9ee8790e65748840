/* C test of the coverage part of the C ABI (hdl/ffi/include/pmu50.h), pure C99. Built and run by
 * hdl/ffi/tests/coverage.rs (cargo test -p pmu50-ffi --test coverage):
 *   cc -std=c99 -Wall -Wextra -pedantic -Werror -I hdl/ffi/include hdl/ffi/tests/coverage.c \
 *      target/release/libpmu50_ffi.a -lpthread -ldl -lm -o coverage_c && ./coverage_c OUT.json EDGES
 * Samples EDGES edges of the shared coverage stimulus (the same splitmix64 draws as
 * hdl/ffi/tests/coverage.rs and python/tests/test_coverage.py) into a coverage handle, checks the
 * error paths (NULL, bad UTF-8, unknown names, mismatched structure), and writes OUT.json as run
 * "c/stimulus/1". Prints "C coverage test: OK ..." and exits 0. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pmu50.h"

#define CHECK(c) do { if (!(c)) { printf("FAIL line %d: %s (%s)\n", __LINE__, #c, pmu50_last_error()); return 1; } } while (0)

static uint64_t state;

static uint64_t next(void) {
    uint64_t z;
    state += 0x9E3779B97F4A7C15ull;
    z = state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* The configuration of the stimulus: short windows and intervals (ticks of 10 us). */
static void stimulus_params(pmu50_params *p) {
    pmu50_params_default(p);
    p->pw = 1; p->pi = 2; p->ps = 1; p->si_max = 30; p->si_min = 10;
    p->t1 = 10; p->t2 = 5; p->cth = 2; p->smp_on = 3;
}

int main(int argc, char **argv) {
    if (argc != 3) {
        printf("usage: %s OUT.json EDGES\n", argv[0]);
        return 2;
    }
    long edges = atol(argv[2]);
    pmu50_params p;
    stimulus_params(&p);
    pmu50_t *m = pmu50_new(&p);
    pmu50_coverage_t *c = pmu50_coverage_new(&p, 10000);
    CHECK(m != NULL && c != NULL);

    /* errors: NULL, illegal parameters, bad names and strings, another structure */
    CHECK(pmu50_coverage_new(NULL, 10000) == NULL);
    pmu50_params bad = p;
    bad.si_min = 0;
    CHECK(pmu50_coverage_new(&bad, 10000) == NULL && strstr(pmu50_last_error(), "min") != NULL);
    pmu50_inputs in;
    memset(&in, 0, sizeof in);
    pmu50_outputs o;
    CHECK(pmu50_coverage_step(NULL, m, &in, &o) == PMU50_ERR_NULL);
    CHECK(pmu50_coverage_step(c, NULL, &in, &o) == PMU50_ERR_NULL);
    CHECK(pmu50_coverage_step(c, m, NULL, &o) == PMU50_ERR_NULL);
    pmu50_params narrow = p;
    narrow.cnt_width = 4;
    pmu50_t *m4 = pmu50_new(&narrow);
    CHECK(pmu50_coverage_step(c, m4, &in, &o) == PMU50_ERR_PARAM && strstr(pmu50_last_error(), "cnt_width") != NULL);
    pmu50_free(m4);
    CHECK(pmu50_tick(m) == 0 && pmu50_coverage_edges(c) == 0);
    CHECK(pmu50_coverage_find(NULL) == PMU50_ERR_NULL);
    CHECK(pmu50_coverage_find("fig17.path.nope") == PMU50_ERR_NAME);
    CHECK(pmu50_coverage_find("\xff\xfe") == PMU50_ERR_TEXT && strstr(pmu50_last_error(), "UTF-8") != NULL);
    CHECK(pmu50_coverage_write(c, argv[1], "\xc3\x28", "pass") == PMU50_ERR_TEXT);
    CHECK(pmu50_coverage_write(c, argv[1], "", "pass") == PMU50_ERR_TEXT);
    CHECK(pmu50_coverage_write(NULL, argv[1], "x", "pass") == PMU50_ERR_NULL);
    CHECK(pmu50_coverage_write(c, "/nonexistent-dir/x/coverage.json", "x", "pass") == PMU50_ERR_IO);
    uint64_t h = 0;
    CHECK(pmu50_coverage_hits(c, pmu50_coverage_bin_count(), &h) == PMU50_ERR_RANGE);
    CHECK(pmu50_coverage_hits(c, 0, NULL) == PMU50_ERR_NULL);
    CHECK(pmu50_coverage_bin_info(pmu50_coverage_bin_count(), NULL, NULL, NULL) == PMU50_ERR_RANGE);
    const char *paths[1] = {"/nonexistent-dir/coverage.json"};
    CHECK(pmu50_coverage_merge(paths, 1, "/tmp/never-written.json") == PMU50_ERR_IO);
    CHECK(pmu50_coverage_merge(NULL, 1, "x.json") == PMU50_ERR_NULL);

    /* bins by index and by name */
    size_t nbins = pmu50_coverage_bin_count();
    CHECK(nbins > 100);
    const char *name = NULL, *why = NULL;
    uint8_t cross = 9;
    int k17 = pmu50_coverage_find("fig17.path.s6_shorten");
    CHECK(k17 >= 0 && pmu50_coverage_bin_info((size_t)k17, &name, &cross, &why) == PMU50_OK);
    CHECK(strcmp(name, "fig17.path.s6_shorten") == 0 && cross == 0 && why == NULL);
    int kboth = pmu50_coverage_find("fig18.history.both");
    CHECK(kboth >= 0 && pmu50_coverage_bin_info((size_t)kboth, NULL, NULL, &why) == PMU50_OK && why != NULL);
    CHECK(pmu50_coverage_bin_info(nbins - 1, &name, &cross, NULL) == PMU50_OK && cross == 1 && strncmp(name, "cross.", 6) == 0);
    CHECK(strncmp(pmu50_coverage_model(), "pmu50-coverage/", 15) == 0);

    /* the shared stimulus */
    state = 1;
    unsigned ig = 0, fault = 0, cs = 0, cc = 0;
    pmu50_internals x;
    uint64_t kons = 0;
    for (long e = 0; e < edges; e++) {
        uint64_t r = next();
        if ((r & 0xFF) < 3) ig ^= 1;
        if (((r >> 8) & 0x3F) == 0) fault ^= 1;
        if (((r >> 14) & 0x1F) == 0) cs ^= 1;
        if (((r >> 19) & 0x1F) == 0) cc ^= 1;
        in.ig = (uint8_t)ig;
        in.vs2_ok = (uint8_t)!fault;
        in.cmp_s = (uint8_t)cs;
        in.cmp_c = (uint8_t)cc;
        in.bus_we = (uint8_t)(((r >> 24) & 0x1F) == 0);
        in.bus_addr = (uint8_t)((r >> 29) % 24);
        in.bus_wdata = (uint16_t)(((r >> 34) & 1) ? (r >> 40) % 64 : (r >> 40) % 1024);
        CHECK(pmu50_coverage_step_traced(c, m, &in, &x, &o) == PMU50_OK);
        kons += x.kon;
    }
    CHECK(pmu50_coverage_edges(c) == (uint64_t)edges && pmu50_tick(m) == (uint64_t)edges);
    /* the core stepped by the coverage is the core: lockstep compare of its internals works */
    CHECK(pmu50_check(m, &o, NULL, &x) == 0);
    int kon_bin = pmu50_coverage_find("key.edge.on");
    CHECK(kon_bin >= 0 && pmu50_coverage_hits(c, (size_t)kon_bin, &h) == PMU50_OK && h == kons && kons > 0);
    size_t hit = 0, reachable = 0;
    CHECK(pmu50_coverage_closure(c, &hit, &reachable) == PMU50_OK && hit > 0 && hit <= reachable && reachable < nbins);
    CHECK(pmu50_coverage_write(c, argv[1], "c/stimulus/1", "pass") == PMU50_OK);

    pmu50_coverage_free(c);
    pmu50_coverage_free(NULL);
    pmu50_free(m);
    printf("C coverage test: OK (%ld edges, %zu of %zu reachable bins hit)\n", edges, hit, reachable);
    return 0;
}
