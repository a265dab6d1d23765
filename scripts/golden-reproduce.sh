#!/usr/bin/env bash
# Checks that `sceneinfo reproduce --json` (every thesis table we recompute, with the default
# 400,000 lines and seed 2002) prints exactly the numbers committed in
# tests/data/golden/reproduce.json, wall-clock values removed. Run it before and after a
# refactoring that must not move a bit (a minute or two in release). With --bless it
# rewrites the file instead (say why in CHANGELOG.md).
#
#   scripts/golden-reproduce.sh [--bless]
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q -p sceneinfo-cli
# The binary cargo just built, wherever CARGO_TARGET_DIR puts it
bin="${CARGO_TARGET_DIR:-target}/release/sceneinfo"
golden=tests/data/golden/reproduce.json
# "seconds":1.5 and "seconds":{"ours":1.5} → <clock>
strip() { sed -E 's/"([a-z_]*second[a-z_]*)":(\{"ours":)?-?[0-9.eE+-]+\}?/"\1":<clock>/g'; }
got=$("$bin" reproduce --json | strip)
if [[ "${1:-}" == "--bless" ]]; then
    printf '%s\n' "$got" > "$golden"
    echo "wrote $golden"
    exit 0
fi
if diff <(printf '%s\n' "$got" | tr ',' '\n') <(tr ',' '\n' < "$golden") > /tmp/golden-reproduce.diff; then
    echo "reproduce: every printed number identical to $golden"
else
    echo "reproduce: printed numbers moved (first differences, one JSON field per line):"
    head -40 /tmp/golden-reproduce.diff
    exit 1
fi
