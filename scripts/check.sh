#!/usr/bin/env bash
# What CI runs (.ci/run installs the system packages, then runs this). Run it locally
# before pushing: formatting, lints as errors, docs, then the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."

echo "== cargo fmt --check"
cargo fmt --all --check

echo "== cargo clippy (warnings are errors)"
cargo clippy --workspace --all-targets --locked -- -D warnings

echo "== cargo doc (warnings are errors)"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --locked --quiet

echo "== image tests on the 4-lane fallback (STEREOTRACE_LANES=4)"
STEREOTRACE_LANES=4 cargo test --locked -p tracer -p stereo -p stereotrace-tests

echo "== image tests at AVX-512's 16 lanes (STEREOTRACE_LANES=16), where this CPU has them"
if STEREOTRACE_LANES=16 cargo run --quiet --locked -p viewer -- render --width 8 --height 8 --json >/dev/null 2>&1; then
    STEREOTRACE_LANES=16 cargo test --locked -p tracer -p stereo -p stereotrace-tests
else
    echo "skipped: this CPU has no AVX-512 (STEREOTRACE_LANES=16 is refused here)"
fi

echo "== cargo test --workspace"
cargo test --workspace --locked
