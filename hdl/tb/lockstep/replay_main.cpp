// Verilator alone replaying a vector file, as an HDL team's own testbench would: the peer of
// `pmu50 regress --dut verilator` in `make bench` (benches/regress_speed.rs).
//
//   replay LIB.so FILE.vec
//
// LIB.so is an RTL library of hdl/tb/lockstep/dut_lib.cpp (as `pmu50 regress --dut verilator`
// builds it, for one set of Verilog parameters), FILE.vec a vector file (`pmu50 vectors`,
// docs/spec.md 6.2). Every parameter the library was built with must equal the file's `// param`
// line. Every input line is one tick (two evaluations); the outputs are folded into a checksum,
// nothing is compared. Prints `ticks=<n> checksum=<hex>`; exit 2 on bad input.
//
// Build: g++ -O2 -o replay hdl/tb/lockstep/replay_main.cpp -ldl
#include <dlfcn.h>

#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace {

int fail(const char *what, const char *detail) {
    std::fprintf(stderr, "replay: %s: %s\n", what, detail);
    return 2;
}

template <typename F> F sym(void *lib, const char *name) { return reinterpret_cast<F>(dlsym(lib, name)); }

// The first `n` whitespace-separated hex fields of a line; false when there are fewer.
bool hex_fields(const char *s, unsigned *f, int n) {
    for (int k = 0; k < n; ++k) {
        while (*s == ' ' || *s == '\t') ++s;
        unsigned v = 0;
        const char *start = s;
        for (;; ++s) {
            unsigned d = *s >= '0' && *s <= '9' ? *s - '0' : *s >= 'a' && *s <= 'f' ? *s - 'a' + 10 : *s >= 'A' && *s <= 'F' ? *s - 'A' + 10 : 16;
            if (d == 16) break;
            v = v << 4 | d;
        }
        if (s == start) return false;
        f[k] = v;
    }
    return true;
}

}  // namespace

int main(int argc, char **argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s LIB.so FILE.vec\n", argv[0]);
        return 2;
    }
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) return fail(argv[1], dlerror());
    auto count = sym<uint32_t (*)(uint32_t)>(lib, "pmu50_dut_count");
    auto name = sym<const char *(*)(uint32_t, uint32_t)>(lib, "pmu50_dut_name");
    auto value = sym<uint64_t (*)(uint32_t)>(lib, "pmu50_dut_param");
    auto make = sym<void *(*)()>(lib, "pmu50_dut_new");
    auto step = sym<uint64_t (*)(void *, const uint64_t *, uint64_t)>(lib, "pmu50_dut_step");
    auto release = sym<void (*)(void *)>(lib, "pmu50_dut_free");
    if (!count || !name || !value || !make || !step || !release) return fail(argv[1], "not a pmu50 RTL library (dut_lib.cpp)");

    FILE *fp = std::fopen(argv[2], "r");
    if (!fp) return fail(argv[2], std::strerror(errno));
    std::map<std::string, uint64_t> param;
    std::vector<uint64_t> in;  // 7 values a tick
    in.reserve(1 << 20);
    char line[512];
    long n = 0;
    while (std::fgets(line, sizeof line, fp)) {
        ++n;
        char key[64];
        unsigned long long v;
        if (line[0] == '/') {
            if (std::sscanf(line, "// param %63s %llu", key, &v) == 2) param[key] = v;
            continue;
        }
        unsigned f[7];
        if (!hex_fields(line, f, 7)) {
            std::fprintf(stderr, "replay: %s:%ld: not a vector line\n", argv[2], n);
            return 2;
        }
        for (unsigned x : f) in.push_back(x);
    }
    std::fclose(fp);
    for (uint32_t i = 0; i < count(4); ++i) {
        auto it = param.find(name(4, i));
        if (it == param.end() || it->second != value(i)) return fail(argv[2], "a parameter differs from the library's");
    }
    void *dut = make();
    uint64_t acc = 0xcbf29ce484222325ull;
    for (size_t k = 0; k + 7 <= in.size(); k += 7) acc = step(dut, &in[k], acc);
    release(dut);
    std::printf("ticks=%zu checksum=%016" PRIx64 "\n", in.size() / 7, acc);
    return 0;
}
