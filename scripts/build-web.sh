#!/usr/bin/env bash
# Builds the browser demo in wasm/www/ (the page loads wasm/www/pkg/, which this writes):
#
#   ./scripts/build-web.sh            # build only
#   ./scripts/build-web.sh --serve    # build, then serve wasm/www on http://127.0.0.1:8000/
#   ./scripts/build-web.sh --serve 9000
#
# Needs the wasm32-unknown-unknown target and wasm-bindgen-cli of the version pinned in
# wasm/Cargo.toml (scripts/test.sh installs both). The `wasm-release` profile (root
# Cargo.toml) optimises for size: opt-level "s", LTO, one codegen unit, panic = abort.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."
export PATH="$HOME/.cargo/bin:$PATH"

wasm=${CARGO_TARGET_DIR:-target}/wasm32-unknown-unknown/wasm-release/sceneinfo_wasm.wasm
out=wasm/www/pkg

rm -rf "$out"
cargo build -p sceneinfo-wasm --target wasm32-unknown-unknown --profile wasm-release
wasm-bindgen --target web --no-typescript --out-dir "$out" "$wasm"
printf 'wasm size: %s bytes (%s), %s bytes (%s/sceneinfo_wasm_bg.wasm)\n' \
    "$(stat -c %s "$wasm")" "$wasm" "$(stat -c %s "$out/sceneinfo_wasm_bg.wasm")" "$out"

if [[ ${1:-} == --serve ]]; then
    port=${2:-8000}
    echo "serving wasm/www on http://127.0.0.1:$port/ (Ctrl-C stops)"
    exec python3 -m http.server "$port" --bind 127.0.0.1 --directory wasm/www
fi
