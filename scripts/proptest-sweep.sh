#!/usr/bin/env bash
# Explores new property-test cases: every test of the workspace in release, with many cases a
# property and a fresh seed (printed), carrying on past failures. `scripts/test.sh` (and CI)
# draws from a fixed seed so that a commit's run is repeatable; this is where new cases come
# from. A failure prints proptest's minimal case and saves it under `proptest-regressions/`:
# commit that file with the fix, so every later run replays it.
#
#   scripts/proptest-sweep.sh [CASES] [SEED]      (defaults: 3000 cases, a random seed)
#
# The whole log goes to target/proptest-sweep.log; the end prints what failed. At 3000 cases
# the run took 36 minutes on 2 shared cores (session 19), most of it the occluded random rooms.
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
CASES=${1:-3000}
SEED=${2:-$(od -An -N4 -tu4 /dev/urandom | tr -d ' ')}
if ! [[ $CASES =~ ^[1-9][0-9]*$ && $SEED =~ ^[0-9]+$ ]]; then
    echo "usage: $0 [CASES] [SEED]" >&2
    exit 2
fi
mkdir -p target
LOG=target/proptest-sweep.log
echo "property tests: $CASES cases each, seed $SEED (log: $LOG)"
PROPTEST_CASES=$CASES PROPTEST_RNG_SEED=$SEED \
    cargo test --release --workspace --no-fail-fast >"$LOG" 2>&1
status=$?
echo "--- failed tests and their minimal cases (seed $SEED, $CASES cases):"
grep -E "^test .* FAILED|^Test failed|minimal failing input" "$LOG" || echo "none"
exit $status
