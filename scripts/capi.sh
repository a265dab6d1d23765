#!/usr/bin/env bash
# sceneinfo's C library (capi/): its header, its pkg-config file, and its check.
#
#   scripts/capi.sh header          rewrite capi/include/sceneinfo.h (cbindgen, pinned in capi/Cargo.toml)
#   scripts/capi.sh pc              write target/capi/pkgconfig/sceneinfo.pc for the build tree
#   scripts/capi.sh install PREFIX  build (release) and install lib, header and .pc into PREFIX
#   scripts/capi.sh check           the test stage (scripts/test.sh runs it): build, header up
#                                   to date, C and C++ examples under AddressSanitizer, their
#                                   numbers against the CLI's bit for bit, failures as errors
#
# The C compilers are the system's: CC (default cc) and CXX (default c++).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
ROOT=$PWD
export PATH="$HOME/.cargo/bin:$PATH"

CC=${CC:-cc}
CXX=${CXX:-c++}
TARGET=${CARGO_TARGET_DIR:-$ROOT/target}
OUT=$TARGET/capi
HEADER=capi/include/sceneinfo.h
VERSION=$(awk -F'"' '/^version = / { print $2; exit }' Cargo.toml)

x() {
    printf '+ %s\n' "$*"
    "$@"
}

# Rewrites the committed header with the cbindgen library pinned in capi/Cargo.toml
# (capi/tests/header.rs; nothing to install).
write_header() {
    SCENEINFO_WRITE_HEADER=1 x cargo test -q -p sceneinfo-capi --test header
}

# Writes sceneinfo.pc with these paths into folder $4.
write_pc() {
    local prefix=$1 libdir=$2 includedir=$3 dir=$4
    mkdir -p "$dir"
    sed -e "s|@PREFIX@|$prefix|" -e "s|@LIBDIR@|$libdir|" -e "s|@INCLUDEDIR@|$includedir|" \
        -e "s|@VERSION@|$VERSION|" capi/sceneinfo.pc.in >"$dir/sceneinfo.pc"
}

cmd_header() {
    write_header
    echo "wrote $HEADER"
}

cmd_pc() {
    write_pc "$ROOT" "$TARGET/debug" "$ROOT/capi/include" "$OUT/pkgconfig"
    echo "wrote $OUT/pkgconfig/sceneinfo.pc (build tree: PKG_CONFIG_PATH=$OUT/pkgconfig)"
}

cmd_install() {
    local prefix=${1:?usage: scripts/capi.sh install PREFIX}
    x cargo build --release -p sceneinfo-capi
    install -d "$prefix/lib/pkgconfig" "$prefix/include"
    install -m 644 "$TARGET/release/libsceneinfo_capi.a" "$prefix/lib/"
    install -m 755 "$TARGET/release/libsceneinfo_capi.so" "$prefix/lib/"
    install -m 644 "$HEADER" "$prefix/include/"
    write_pc "$prefix" "$prefix/lib" "$prefix/include" "$prefix/lib/pkgconfig"
    echo "installed into $prefix (PKG_CONFIG_PATH=$prefix/lib/pkgconfig)"
}

# Runs a C example and the CLI command of its name (measure or radiosity) on one scene
# and job, and compares their numbers (for measure, every form factor too).
# compare COMMAND NAME SCENE [LINES SEED THREADS METHOD [ka]]  (ka: --emit-from-ka)
compare() {
    local command=$1 name=$2 scene=$3 lines=${4:-0} seed=${5:-1} threads=${6:-1}
    local method=${7:-global} ka=${8:-} flags=() args=() matrix=()
    if [[ $lines != 0 ]]; then
        flags=(--lines "$lines" --seed "$seed" --method "$method" --threads 1)
        args=("$lines" "$seed" "$threads" "$method")
    fi
    if [[ -n $ka ]]; then
        flags+=(--emit-from-ka)
        args+=(ka)
    fi
    if [[ $command == measure ]]; then
        matrix=("$OUT/$name.F.csv")
        flags+=(--matrix "$OUT/$name.F.csv")
    fi
    printf '  %s: C %s %s %s vs sceneinfo %s --json %s\n' "$name" "$command" \
        "$(basename "$scene")" "${args[*]}" "$command" "${flags[*]}"
    "$OUT/$command" "$scene" "${args[@]}" >"$OUT/$name.c.json" 2>"$OUT/$name.c.err"
    "$TARGET/debug/sceneinfo" "$command" "$scene" --json "${flags[@]}" \
        >"$OUT/$name.cli.json" 2>/dev/null
    python3 capi/tests/compare_cli.py "$OUT/$name.c.json" "$OUT/$name.cli.json" "${matrix[@]}"
}

# Every bad file of the catalogue that `sceneinfo measure FILE` refuses without flags:
# the C example must exit 2 with the CLI's `FILE:N: what` (or `FILE: what`).
bad_files() {
    local n=0 file args message want got
    while IFS='|' read -r file args message; do
        file=${file//[[:space:]]/}
        message=${message# }
        [[ -z $file || $file == \#* || $args =~ [^[:space:]] ]] && continue
        if [[ $message =~ ^line\ ([0-9]+):\ (.*)$ ]]; then
            want="tests/data/bad/$file:${BASH_REMATCH[1]}: ${BASH_REMATCH[2]}"
        else
            want="tests/data/bad/$file: $message"
        fi
        if "$OUT/measure" "tests/data/bad/$file" >/dev/null 2>"$OUT/bad.err"; then
            echo "tests/data/bad/$file: accepted, but the catalogue says: $message"
            return 1
        fi
        got=$(grep -v '^measure: warning' "$OUT/bad.err" || true)
        if [[ $got != *"$want" ]]; then
            printf '%s:\n  want ...%s\n  got  %s\n' "$file" "$want" "$got"
            return 1
        fi
        n=$((n + 1))
    done <tests/data/bad/expected.txt
    echo "  bad inputs: $n files of tests/data/bad refused with the CLI's file:line: message"
}

# The C test of exact form factors with occlusion against `sceneinfo formfactors --tol`:
# every entry and its error estimate, bit for bit.
exact_with_occlusion() {
    local scene=tests/data/vs3/room_with_plate.vs3 tol=1e-3
    printf '+ %s\n' "$OUT/exact $scene $tol"
    "$OUT/exact" "$scene" "$tol" >"$OUT/exact.c.txt"
    "$TARGET/debug/sceneinfo" formfactors "$scene" --tol "$tol" --out "$OUT/exact.ijv" >/dev/null
    compare_ijv "$OUT/exact.c.txt" "$OUT/exact.ijv"
}

# Compares a C program's `i,j,F_ij,error` lines with the CLI's `.ijv` file, bit for bit
# (an empty error field of the CLI: NaN in C).
compare_ijv() {
    python3 - "$1" "$2" <<'EOF'
import math, struct, sys
c = [l.split(",") for l in open(sys.argv[1]).read().splitlines()]
cli = [l.split(",") for l in open(sys.argv[2]).read().splitlines()[1:]]
bits = lambda x: struct.pack("<d", float(x))
if len(c) != len(cli):
    sys.exit(f"C gave {len(c)} entries, the CLI {len(cli)}")
for a, b in zip(c, cli):
    err_same = math.isnan(float(a[3])) if b[3] == "" else bits(a[3]) == bits(b[3])
    if a[:2] != b[:2] or bits(a[2]) != bits(b[2]) or not err_same:
        sys.exit(f"C {a} vs CLI {b}")
print(f"    bit-identical: {len(c)} entries of F and their error estimates")
EOF
}

# The C test of exact rows: a job split in two ranges, written, read, merged and measured
# through the C API against the CLI's `formfactors --rows --partial` and `merge --out`: the
# partial files byte for byte, every merged entry and its estimate bit for bit.
exact_rows_merged() {
    # 9 patches: the hexagon's two pieces are one (a merge short of rows would fail)
    local scene=tests/data/vs3/room_with_plate.vs3 tol=1e-3 split=4 n=9 dir="$OUT/exact-rows"
    local S="$TARGET/debug/sceneinfo"
    rm -rf "$dir" && mkdir -p "$dir"
    printf '+ %s\n' "$OUT/rows $scene $tol $split $dir"
    "$OUT/rows" "$scene" "$tol" "$split" "$dir" >"$dir/merged.c.txt"
    "$S" formfactors "$scene" --tol "$tol" --rows "0..$split" --partial "$dir/cli0.sir" >/dev/null
    "$S" formfactors "$scene" --tol "$tol" --rows "$split..$n" --partial "$dir/cli1.sir" >/dev/null
    "$S" merge "$dir/cli0.sir" "$dir/cli1.sir" --out "$dir/merged.ijv" >/dev/null
    cmp "$dir/c0.sir" "$dir/cli0.sir" && cmp "$dir/c1.sir" "$dir/cli1.sir"
    echo "    byte-identical: the C and CLI partial files of rows 0..$split and $split..$n"
    compare_ijv "$dir/merged.c.txt" "$dir/merged.ijv"
}

cmd_check() {
    command -v "$CC" >/dev/null || { echo "no C compiler ($CC)"; return 1; }
    command -v "$CXX" >/dev/null || { echo "no C++ compiler ($CXX)"; return 1; }
    command -v pkg-config >/dev/null || { echo "no pkg-config"; return 1; }
    command -v python3 >/dev/null || { echo "no python3 (it compares the JSON)"; return 1; }
    x cargo build -p sceneinfo-capi -p sceneinfo-cli

    echo "== the committed header is cbindgen's output"
    x cargo test -q -p sceneinfo-capi --test header

    echo "== the examples, through pkg-config, under AddressSanitizer"
    cmd_pc
    export PKG_CONFIG_PATH="$OUT/pkgconfig"
    local cflags libs san
    cflags=$(pkg-config --cflags sceneinfo)
    libs=$(pkg-config --libs sceneinfo)
    san=(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all -g)
    # shellcheck disable=SC2086 # the pkg-config flags are words
    {
        x "$CC" -std=c11 -Wall -Wextra -Wpedantic -Werror "${san[@]}" $cflags \
            capi/examples/measure.c -o "$OUT/measure" $libs -Wl,-rpath,"$TARGET/debug" -lm
        x "$CC" -std=c11 -Wall -Wextra -Wpedantic -Werror "${san[@]}" $cflags \
            capi/examples/radiosity.c -o "$OUT/radiosity" $libs -Wl,-rpath,"$TARGET/debug"
        x "$CC" -std=c11 -Wall -Wextra -Werror "${san[@]}" $cflags \
            capi/tests/errors.c -o "$OUT/errors" $libs -Wl,-rpath,"$TARGET/debug" -lm
        x "$CC" -std=c11 -Wall -Wextra -Wpedantic -Werror "${san[@]}" $cflags \
            capi/tests/exact.c -o "$OUT/exact" $libs -Wl,-rpath,"$TARGET/debug" -lm
        x "$CC" -std=c11 -Wall -Wextra -Wpedantic -Werror "${san[@]}" $cflags \
            capi/tests/rows.c -o "$OUT/rows" $libs -Wl,-rpath,"$TARGET/debug" -lm
        x "$CC" -std=c11 -Wall -Wextra -Wpedantic -Werror "${san[@]}" $cflags \
            capi/tests/view3d.c -o "$OUT/view3d" $libs -Wl,-rpath,"$TARGET/debug" -lm
        # The C++ example links the static library
        x "$CXX" -std=c++17 -Wall -Wextra -Werror "${san[@]}" $cflags \
            capi/examples/measure.cpp -o "$OUT/measure_cpp" \
            "$TARGET/debug/libsceneinfo_capi.a" $(pkg-config --static --libs-only-l sceneinfo |
                sed 's/-lsceneinfo_capi//')
    }
    export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
    export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

    echo "== C and CLI, the same bits (report values and every form factor)"
    local flat="$OUT/three-objects-2.flat"
    local cornell=tests/data/corpus/obj/cornell_box/cornell_box.obj
    "$TARGET/debug/sceneinfo" scene catalogue three-objects-2 >"$flat"
    compare measure flat-exact "$flat"
    compare measure flat-global "$flat" 200000 7 3 global
    compare measure flat-local "$flat" 100000 11 2 local
    compare measure cornell-global "$cornell" 100000 3 2 global
    compare measure cornell-bundle "$cornell" 70000 5 2 bundle
    # The mesh formats, through the readers the CLI uses (crate sceneinfo-formats)
    compare measure glb-global tests/data/corpus/gltf/BoxTextured-Binary/BoxTextured.glb \
        100000 7 2 global
    compare measure gltf-local tests/data/corpus/gltf/BoxTextured/BoxTextured.gltf \
        100000 3 2 local
    compare measure ply-global \
        tests/data/corpus/ply/openmesh/cube-minimal-extra-elements-binary.ply 100000 7 2 global

    echo "== radiosity: C and CLI, the same bits (measures, B per channel, I_S^c)"
    local lit=capi/tests/lit.flat lit3="$OUT/cornell-lit.obj"
    "$TARGET/debug/sceneinfo" scene solid cornell -o "$lit3" >/dev/null
    compare radiosity lit-exact "$lit"
    compare radiosity lit-global "$lit" 100000 3 2 global
    compare radiosity lit3-global "$lit3" 100000 9 3 global
    compare radiosity cornell-ka-local "$cornell" 100000 4 2 local ka

    echo "== the C++ example"
    "$OUT/measure_cpp" "$flat" | tee "$OUT/cpp.txt"
    python3 - "$OUT/cpp.txt" "$OUT/flat-exact.cli.json" <<'EOF'
import json, re, struct, sys
text = open(sys.argv[1]).read()
cli = json.load(open(sys.argv[2]))
i_s, h_s = (float(v) for v in re.findall(r"= (\S+) bits", text))
same = lambda a, b: struct.pack("<d", a) == struct.pack("<d", b)
if not (same(i_s, cli["i_s"]) and same(h_s, cli["h_s"])):
    sys.exit(f"C++ I_S {i_s!r}, H_S {h_s!r}; CLI {cli['i_s']!r}, {cli['h_s']!r}")
print("    bit-identical: I_S and H_S")
EOF

    echo "== exact form factors with occlusion (a View3D .vs3 scene): C and CLI, the same bits"
    exact_with_occlusion
    x "$OUT/view3d" tests/data/vs3/surface-kinds/window.vs3

    echo "== exact rows in two ranges, merged: C and CLI, the same files and bits"
    exact_rows_merged

    echo "== failures are statuses and messages"
    x "$OUT/errors" tests/data/bad/not_a_number.flat "$cornell" capi/tests/lit.flat
    bad_files
}

case ${1:-} in
header) cmd_header ;;
pc) cmd_pc ;;
install) cmd_install "${2:-}" ;;
check) cmd_check ;;
*)
    sed -n '2,11p' "$0"
    exit 2
    ;;
esac
