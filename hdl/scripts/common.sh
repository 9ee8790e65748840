# Shared by the shell scripts of hdl/ (sourced, never run): where things are, and the two readers
# that every runner of a vector file needs.
#
#   HDL, ROOT, PMU50            hdl/, the repository root, the release CLI
#   vec_params FILE PREFIX      ARGS+=("PREFIX<NAME>=<VALUE>" ...) for every `// param NAME VALUE`
#                               line of the vector file's header (it ends at the first data line),
#                               then "PREFIXCLOCK_NS=<ns>" (`// clock_ns N`, or `// param CLOCK_US
#                               N` x 1000; default 10000); CLOCK_NS is set too
#   rtl_files [FILELIST]        RTL=(...) the files of a Verilog file list, default PMU50_FILELIST
#                               or hdl/pmu50.f: paths relative to the list's folder, blank lines
#                               and // or # comments skipped (as `pmu50 regress --rtl` passes it);
#                               FLIST is the list read
HDL="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ROOT="$(cd "$HDL/.." && pwd)"
PMU50="$ROOT/target/release/pmu50"
# The model's C library (crate pmu50-ffi). cargo writes it to target/release/deps/ whenever it
# compiles the crate, `cargo test` included; the copy in target/release/ is made only by a `cargo
# build` that compiled it, so after the tests' build it may be missing or older.
PMU50_FFI_LIB="$ROOT/target/release/deps/libpmu50_ffi.a"
[ -f "$PMU50_FFI_LIB" ] || PMU50_FFI_LIB="$ROOT/target/release/libpmu50_ffi.a"

vec_params() {
    local file="$1" prefix="$2" line
    CLOCK_NS=10000
    while IFS= read -r line; do
        case "$line" in
            "// param CLOCK_US "*) CLOCK_NS=$(( ${line##* } * 1000 )) ;;
            "// param "*) set -- $line; ARGS+=("$prefix$3=$4") ;;
            "// clock_ns "*) CLOCK_NS="${line##* }" ;;
            //*) ;;
            *) break ;;
        esac
    done < "$file"
    ARGS+=("${prefix}CLOCK_NS=$CLOCK_NS")
}

rtl_files() {
    local fdir
    FLIST="${1:-${PMU50_FILELIST:-$HDL/pmu50.f}}"
    fdir="$(cd "$(dirname "$FLIST")" && pwd)"
    mapfile -t RTL < <(sed -e 's|//.*||' -e 's|#.*||' -e 's|^[[:space:]]*||' -e 's|[[:space:]]*$||' "$FLIST" | grep -v '^$' | sed "s|^\([^/]\)|$fdir/\1|")
}
