#!/usr/bin/env bash
# The project's whole check, as run by CI (.ci/run) and by developers:
#
#   ./scripts/test.sh
#
# Part 1 installs whatever is missing (each step idempotent, and loud when it installs;
# a failed install stops the script with a non-zero exit). Part 2 runs every check with a
# banner and its duration, carries on past a failing check so one run shows them all, and
# ends with the line "N passed, M failed" (exit status 1 when M > 0).
#
# Tunable, never skippable: FUZZ_SECONDS (default 15) is how long each fuzz target runs;
# PROPTEST_RNG_SEED (default 2002) the seed every property test draws its cases from.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
ROOT=$PWD
export PATH="$HOME/.cargo/bin:$PATH"
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"

# Property tests draw their cases from one seed (proptest's PROPTEST_RNG_SEED), so a run of a
# commit is repeatable and a failure seen by CI reproduces on any machine. Exploring new cases
# is a separate, deliberate step: scripts/proptest-sweep.sh (many cases, a fresh seed).
export PROPTEST_RNG_SEED=${PROPTEST_RNG_SEED:-2002}

FUZZ_SECONDS=${FUZZ_SECONDS:-15}
[[ $FUZZ_SECONDS =~ ^[1-9][0-9]*$ ]] || { echo "FUZZ_SECONDS must be a positive integer" >&2; exit 2; }
CARGO_FUZZ_VERSION=0.13.2
E2E_DIR=wasm/tests/e2e
CHROMIUM=${CHROMIUM:-/usr/bin/chromium}
export CHROMIUM

SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO=sudo; fi

# ---------------------------------------------------------------------------------------
# Part 1: install what is missing
# ---------------------------------------------------------------------------------------

say() { printf '\n==> %s\n' "$*"; }
ok() { printf '    ok: %s\n' "$*"; }
die() {
    printf '\n!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!\n' >&2
    printf '!!! INSTALL FAILED: %s\n' "$*" >&2
    printf '!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!\n' >&2
    exit 1
}

install_rust_components() {
    say "install: rustfmt, clippy (active toolchain)"
    command -v rustup >/dev/null || die "rustup is not installed (see https://rustup.rs)"
    local installed
    installed=$(rustup component list --installed)
    for c in rustfmt clippy; do
        if grep -q "^$c-" <<<"$installed"; then
            ok "$c"
        else
            echo "    installing component $c"
            rustup component add "$c" || die "rustup component add $c"
        fi
    done
}

install_targets() {
    say "install: rustup targets wasm32-unknown-unknown, thumbv7em-none-eabihf"
    local installed
    installed=$(rustup target list --installed)
    for t in wasm32-unknown-unknown thumbv7em-none-eabihf; do
        if grep -qx "$t" <<<"$installed"; then
            ok "$t"
        else
            echo "    installing target $t"
            rustup target add "$t" || die "rustup target add $t"
        fi
    done
}

install_nightly() {
    say "install: nightly toolchain (cargo-fuzz needs it)"
    local toolchains
    toolchains=$(rustup toolchain list)
    if grep -q '^nightly-' <<<"$toolchains"; then
        ok "$(rustup run nightly rustc --version)"
    else
        echo "    installing nightly"
        rustup toolchain install nightly --profile minimal || die "rustup toolchain install nightly"
    fi
}

install_cargo_fuzz() {
    say "install: cargo-fuzz $CARGO_FUZZ_VERSION"
    local have
    have=$(cargo fuzz --version 2>/dev/null || true)
    if [[ $have == "cargo-fuzz $CARGO_FUZZ_VERSION" ]]; then
        ok "$have"
    else
        echo "    found '${have:-nothing}'; installing cargo-fuzz =$CARGO_FUZZ_VERSION"
        cargo +nightly install cargo-fuzz --version "=$CARGO_FUZZ_VERSION" --locked --force \
            || die "cargo install cargo-fuzz $CARGO_FUZZ_VERSION"
    fi
}

install_wasm_bindgen() {
    # The CLI must match the wasm-bindgen library exactly ("schema versions must exactly
    # match"); the lock file says which one the wasm crate builds with.
    local want have
    want=$(awk '$0 == "name = \"wasm-bindgen\"" { getline; gsub(/version = |"/, ""); print; exit }' Cargo.lock)
    [[ -n $want ]] || die "no wasm-bindgen package in Cargo.lock"
    say "install: wasm-bindgen-cli $want (the version in Cargo.lock)"
    have=$(wasm-bindgen --version 2>/dev/null || true)
    if [[ $have == "wasm-bindgen $want" ]]; then
        ok "$have"
    else
        echo "    found '${have:-nothing}'; installing wasm-bindgen-cli =$want (takes ~3 min)"
        # Not --locked: one of its locked dependency versions is gone from the registry.
        cargo install wasm-bindgen-cli --version "=$want" --force \
            || die "cargo install wasm-bindgen-cli $want"
        [[ $(wasm-bindgen --version) == "wasm-bindgen $want" ]] \
            || die "wasm-bindgen --version is not $want after the install"
    fi
}

apt_updated=0
apt_install() {
    if [[ $apt_updated -eq 0 ]]; then
        $SUDO apt-get update || die "apt-get update"
        apt_updated=1
    fi
    # The first attempt fails on these machines ("dpkg: error processing archive ... No such
    # file or directory": an apt hook deletes .deb files between dpkg batches); the second
    # one succeeds. See shared/TOOLCHAIN.md.
    if ! $SUDO apt-get install -y "$@"; then
        echo "    apt-get install $* failed once (known dpkg hook problem); retrying"
        $SUDO apt-get install -y "$@" || die "apt-get install $*"
    fi
}

install_chromium() {
    say "install: Debian chromium (headless browser test)"
    if [[ -x $CHROMIUM ]]; then
        ok "$("$CHROMIUM" --version 2>/dev/null | tail -n 1)"
    else
        echo "    installing chromium with apt-get"
        apt_install chromium
        [[ -x $CHROMIUM ]] || die "chromium installed, but $CHROMIUM does not exist"
    fi
}

install_node_and_playwright() {
    say "install: node, playwright-core and binaryen (from $E2E_DIR/package-lock.json)"
    if command -v node >/dev/null && command -v npm >/dev/null; then
        ok "node $(node --version)"
    else
        echo "    installing nodejs and npm with apt-get"
        apt_install nodejs npm
    fi
    # playwright-core drives Chromium; binaryen's wasm-opt shrinks the page's module
    local want have
    want=$(node -p "const l = require('./$E2E_DIR/package-lock.json').packages; \
        ['playwright-core', 'binaryen'].map(p => p + ' ' + l['node_modules/' + p].version).join(', ')") \
        || die "cannot read the package versions from $E2E_DIR/package-lock.json"
    have=$(node -p "['playwright-core', 'binaryen'].map(p => { try { return p + ' ' + \
        require('./$E2E_DIR/node_modules/' + p + '/package.json').version } catch { return p + ' none' } }).join(', ')")
    if [[ $have == "$want" ]]; then
        ok "$have"
    else
        echo "    found '$have'; npm ci in $E2E_DIR ($want)"
        # Only the library: it drives the system Chromium, never a downloaded browser.
        PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --prefix "$E2E_DIR" --no-audit --no-fund \
            || die "npm ci in $E2E_DIR"
    fi
}

install_c_compiler() {
    # The C library's examples are compiled with the system's C and C++ compilers
    say "install: a C and C++ compiler, pkg-config (the C library's examples)"
    if command -v cc >/dev/null && command -v c++ >/dev/null && command -v pkg-config >/dev/null; then
        ok "$(cc --version | head -n 1), pkg-config $(pkg-config --version)"
    else
        echo "    installing gcc, g++ and pkg-config with apt-get"
        apt_install gcc g++ pkg-config
    fi
}

# The Python package's tools, in a venv under target/ (from PyPI, pinned in
# py/requirements-test.txt); python3-venv from Debian if `python3 -m venv` cannot work.
PY_TOOLS=target/py-tools
install_python() {
    say "install: python3 venv with maturin, pytest, hypothesis, numpy, scipy, mypy (py/requirements-test.txt)"
    command -v python3 >/dev/null || apt_install python3
    if [[ ! -x $PY_TOOLS/bin/pip ]]; then
        rm -rf "$PY_TOOLS"
        if ! python3 -m venv "$PY_TOOLS"; then
            echo "    python3 -m venv failed: installing python3-venv with apt-get"
            rm -rf "$PY_TOOLS"
            apt_install python3-venv
            python3 -m venv "$PY_TOOLS" || die "python3 -m venv $PY_TOOLS"
        fi
    fi
    "$PY_TOOLS/bin/pip" install --quiet --disable-pip-version-check -r py/requirements-test.txt \
        || die "pip install -r py/requirements-test.txt"
    ok "$("$PY_TOOLS/bin/python" --version), $("$PY_TOOLS/bin/maturin" --version)"
}

install_start=$(date +%s)
install_rust_components
install_targets
install_nightly
install_cargo_fuzz
install_wasm_bindgen
install_chromium
install_node_and_playwright
install_c_compiler
install_python
printf '\n==> tools ready (%ss)\n' "$(($(date +%s) - install_start))"

# ---------------------------------------------------------------------------------------
# Part 2: the checks
# ---------------------------------------------------------------------------------------

checks_start=$(date +%s)

# A full run writes about 5 GB of build output (4.9 GB in target/ on a fresh clone in
# session 17, plus fuzz/target): the CI host once ran out of disk mid-run, so say how much
# there is before starting.
target_dir=${CARGO_TARGET_DIR:-$ROOT/target}
mkdir -p "$target_dir"
free_kb=$(df -Pk "$target_dir" | awk 'NR == 2 { print $4 }')
printf '\n==> disk: %s MB free where the build goes (%s)\n' "$((free_kb / 1024))" "$target_dir"
if [[ $free_kb -lt $((6 * 1024 * 1024)) ]]; then
    echo "    warning: less than 6 GB free; the run may fail with 'No space left on device'"
fi
passed=0
failed=0
summary=()
failures=()
step_logs=$(mktemp -d)

# run_step NAME FUNCTION...: runs the function in a subshell with errexit on, timing it.
run_step() {
    local name=$1
    shift
    printf '\n'
    printf '=%.0s' {1..90}
    printf '\n=== [%d] %s\n' "$((passed + failed + 1))" "$name"
    printf '=%.0s' {1..90}
    printf '\n'
    local t0 t1 rc secs
    t0=$(date +%s%N)
    local log="$step_logs/$((passed + failed + 1)).log"
    set +e
    (
        set -euo pipefail
        "$@"
    ) 2>&1 | tee "$log"
    rc=${PIPESTATUS[0]}
    set -e
    t1=$(date +%s%N)
    secs=$(awk -v ns="$((t1 - t0))" 'BEGIN { printf "%.1f", ns / 1e9 }')
    if [[ $rc -eq 0 ]]; then
        passed=$((passed + 1))
        summary+=("$(printf 'PASS %7ss  %s' "$secs" "$name")")
        printf '<== PASS  %s (%s s)\n' "$name" "$secs"
    else
        failed=$((failed + 1))
        summary+=("$(printf 'FAIL %7ss  %s (exit %d)' "$secs" "$name" "$rc")")
        printf '<== FAIL  %s (%s s, exit %d)\n' "$name" "$secs" "$rc"
        # What failed, for the summary at the end (CI keeps only the tail of the output):
        # failing test names, panic messages with the line after, compiler errors.
        failures+=("--- $name")
        mapfile -t -O "${#failures[@]}" failures < <(
            grep -E -A2 '^test .* FAILED$|panicked at|^error(\[E[0-9]+\])?:|^---- |^FAILED|^!!! ' "$log" |
                grep -v -E '^note: run with' | head -n 40
        )
    fi
}

# Echoes a command, then runs it.
x() {
    printf '+ %s\n' "$*"
    "$@"
}

FMT_COLOR=never
if [[ -t 1 ]]; then FMT_COLOR=always; fi

check_fmt() {
    x cargo fmt --all -- --check --color "$FMT_COLOR"
    x cargo fmt --manifest-path fuzz/Cargo.toml -- --check --color "$FMT_COLOR"
}

check_clippy() {
    x cargo clippy --workspace --all-targets -- -D warnings
    # wasm/tests/*.rs only compile for wasm32; fuzz/ is its own workspace.
    x cargo clippy -p sceneinfo-wasm --all-targets --target wasm32-unknown-unknown -- -D warnings
    x cargo clippy --manifest-path fuzz/Cargo.toml --all-targets -- -D warnings
    # The API docs: no broken or private intra-doc links.
    RUSTDOCFLAGS="-D warnings" x cargo doc --no-deps --workspace
}

check_tests() {
    x cargo test --workspace --no-fail-fast
}

check_no_std() {
    x cargo build -p sceneinfo --no-default-features --target "$1"
}

check_no_std_alloc() {
    x cargo build -p sceneinfo --no-default-features --features alloc --target "$1"
}

build_wasm() {
    # The README's one command for the page: cargo build (wasm-release) + wasm-bindgen.
    x ./scripts/build-web.sh
}

test_wasm_node() {
    # wasm-bindgen-test-runner (installed with wasm-bindgen-cli) runs wasm/tests/*.rs in node.
    CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUNNER=wasm-bindgen-test-runner \
        x cargo test -p sceneinfo-wasm --target wasm32-unknown-unknown
}

test_browser() {
    [[ -f wasm/www/pkg/sceneinfo_wasm.js ]] || { echo "wasm/www/pkg is missing: the wasm build failed"; return 1; }
    # cli_parity.test.mjs compares the wasm API with the CLI binary (built by cargo test).
    x cargo build -p sceneinfo-cli
    [[ -f wasm/www/pkg3d/sceneinfo_wasm.js ]] || { echo "wasm/www/pkg3d is missing: the wasm build failed"; return 1; }
    # lab3d.test.mjs drives the 3D lab and compares what it shows with the CLI's JSON; it
    # writes the screenshots target/e2e/lab3d_*.png (E2E_FIGURES=docs/figures refreshes the docs').
    SCENEINFO_BIN=${CARGO_TARGET_DIR:-target}/debug/sceneinfo \
        x node --test --test-reporter=spec "$E2E_DIR/cli_parity.test.mjs" "$E2E_DIR/page.test.mjs" \
        "$E2E_DIR/lab3d.test.mjs"
    [[ -s target/e2e/index.png ]] || { echo "no screenshot at target/e2e/index.png"; return 1; }
    printf 'screenshot: target/e2e/index.png (%s bytes)\n' "$(stat -c %s target/e2e/index.png)"
    # Issue 24's budget: the 3D page's wasm and JS together at most 800 KB compressed
    local lab3d_files=(wasm/www/pkg3d/sceneinfo_wasm_bg.wasm wasm/www/pkg3d/sceneinfo_wasm.js
        wasm/www/lab3d.js wasm/www/gl3d.js wasm/www/worker3d.js wasm/www/scene3d.js wasm/www/plots.js)
    local gz=0 f
    for f in "${lab3d_files[@]}"; do gz=$((gz + $(gzip -9 -c "$f" | wc -c))); done
    printf '3D lab: wasm + JS %s bytes compressed (gzip -9; budget 800000)\n' "$gz"
    ((gz <= 800000)) || { echo "the 3D lab is over its 800 KB budget"; return 1; }
}

check_capi() {
    # The C library: build, header up to date, C/C++ examples under ASan against the CLI.
    x ./scripts/capi.sh check
}

# The Python wheel (maturin, dev profile: it reuses the core that test_browser's CLI build
# compiled, so only pyo3, numpy and the bindings compile, about a minute; a --release build
# takes several), installed into a fresh venv with numpy alone, where it must import and
# measure; then pytest (py/tests) with the test tools, against the CLI binary for the parity
# tests, and mypy's stubtest of the .pyi stub.
test_python() {
    local wheels=target/py-wheels clean=target/py-clean wheel
    rm -rf "$wheels" "$clean"
    x "$PY_TOOLS/bin/maturin" build -m py/Cargo.toml --profile dev --out "$wheels"
    wheel=$(ls "$wheels"/sceneinfo-*.whl)
    printf 'wheel: %s (%s bytes)\n' "$wheel" "$(stat -c %s "$wheel")"
    x python3 -m venv "$clean"
    x "$clean/bin/pip" install --quiet --disable-pip-version-check "$wheel"
    x "$clean/bin/python" -c 'import importlib.util as u, sceneinfo as s
assert u.find_spec("scipy") is None, "the clean venv must hold numpy alone"
m = s.measure(s.Scene.preset("cube", grid=3), lines=70000, threads=1)
print("clean venv: sceneinfo imports; cube 54 patches: I_S =", m.i_s, "F", type(m.form_factors()).__name__)'
    x "$PY_TOOLS/bin/pip" install --quiet --disable-pip-version-check --force-reinstall --no-deps "$wheel"
    x cargo build -p sceneinfo-cli
    SCENEINFO_BIN=${CARGO_TARGET_DIR:-target}/debug/sceneinfo \
        x "$PY_TOOLS/bin/python" -m pytest -q -p no:cacheprovider py/tests
    # The .pyi stub against the module as built (names, signatures, classes); from target/
    # so that mypy's cache lands there
    (cd target && x "$ROOT/$PY_TOOLS/bin/python" -m mypy.stubtest sceneinfo)
}

build_fuzz() {
    x cargo +nightly fuzz build --fuzz-dir fuzz
}

# -timeout=30: a slow unit, not a hang, on a loaded machine must not fail the run (the
# pipeline targets solve small scenes exactly; a unit normally takes milliseconds).
run_fuzz() {
    local target=$1
    mkdir -p "fuzz/corpus/$target" "fuzz/seeds/$target"
    if ! x cargo +nightly fuzz run --fuzz-dir fuzz "$target" \
        "$ROOT/fuzz/corpus/$target" "$ROOT/fuzz/seeds/$target" -- \
        -max_total_time="$FUZZ_SECONDS" -max_len=4096 -timeout=30 -rss_limit_mb=2048 \
        -print_final_stats=1; then
        echo "fuzz target $target failed: copy the input from fuzz/artifacts/$target/ into"
        echo "tests/data/fuzz/$target/ so that cargo test replays it"
        return 1
    fi
}

run_step "cargo fmt --check (workspace and fuzz/)" check_fmt
run_step "cargo clippy and rustdoc -D warnings (workspace, wasm32, fuzz/)" check_clippy
run_step "cargo test --workspace" check_tests
run_step "no_std: sceneinfo --no-default-features, thumbv7em-none-eabihf" \
    check_no_std thumbv7em-none-eabihf
run_step "no_std + alloc: sceneinfo --features alloc, thumbv7em-none-eabihf" \
    check_no_std_alloc thumbv7em-none-eabihf
run_step "no_std: sceneinfo --no-default-features, wasm32-unknown-unknown" \
    check_no_std wasm32-unknown-unknown
run_step "wasm: build sceneinfo-wasm (wasm-release) + wasm-bindgen --target web" build_wasm
run_step "wasm: wasm-bindgen-test in node (wasm/tests)" test_wasm_node
run_step "browser: headless Chromium on wasm/www" test_browser
run_step "C library: header, examples under ASan, C vs CLI bit for bit" check_capi
run_step "python: wheel (maturin), import with numpy alone, pytest (py/tests)" test_python
run_step "fuzz: cargo +nightly fuzz build" build_fuzz
for src in fuzz/fuzz_targets/fuzz_*.rs; do
    target=$(basename "$src" .rs)
    run_step "fuzz: $target for ${FUZZ_SECONDS} s" run_fuzz "$target"
done

printf '\n'
printf '=%.0s' {1..90}
printf '\n=== summary (total %s s, of which %s s installing)\n' \
    "$(($(date +%s) - install_start))" "$((checks_start - install_start))"
printf '%s\n' "${summary[@]}"
printf 'build output: %s\n' "$(du -sh "$target_dir" 2>/dev/null | cut -f1) in $target_dir"
if [[ ${#failures[@]} -gt 0 ]]; then
    printf '\n=== what failed (the lines of each failed step that name it)\n'
    printf '%s\n' "${failures[@]}"
fi
printf '=%.0s' {1..90}
printf '\n'
echo "$passed passed, $failed failed"
[[ $failed -eq 0 ]]
