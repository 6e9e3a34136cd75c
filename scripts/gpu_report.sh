#!/usr/bin/env bash
# The GPU report in one call, on a machine with a hardware GPU: a portable
# release build, the throughput bench at 1e5, 1e6 and 4e6 particles (three
# measurements each, every stage timed alone, the work of a step counted),
# then the four-million-particle disks to their end. Every figure lands in
# one folder:
#
#   scripts/gpu_report.sh [OUT]        (default: out/gpu_report)
#
#   OUT/adapter.txt      the adapters the solver sees, the GPU's own report
#   OUT/bench.json       bench --backend gpu --repeat 3 --stages --json
#   OUT/disks_4m/        history.csv and summary.json of the 4e6 run
#   OUT/disks_4m.log     its progress, with the wall time at the end
#
# SPHCONTACT_BIN=path skips the build and uses that binary instead (for a
# machine without a Rust toolchain). SPHCONTACT_REPORT_PARTICLES overrides
# the bench sizes; SPHCONTACT_REPORT_SCENE=0 skips the 4e6 run.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/gpu_report}
mkdir -p "$OUT"

BIN=${SPHCONTACT_BIN:-}
if [ -z "$BIN" ]; then
    # The repository builds for the host CPU (.cargo/config.toml); an empty
    # RUSTFLAGS overrides that, so the binary runs on any x86-64 machine.
    RUSTFLAGS="" cargo build --release --bin sphcontact
    BIN=target/release/sphcontact
fi

{
    date -u
    "$BIN" --version 2>/dev/null || true
    command -v nvidia-smi >/dev/null && nvidia-smi -L || echo "no nvidia-smi"
} >"$OUT/adapter.txt" 2>&1

PARTICLES=${SPHCONTACT_REPORT_PARTICLES:-100000 1000000 4000000}
# shellcheck disable=SC2086
"$BIN" bench --backend gpu --particles $PARTICLES --repeat 3 --stages --json >"$OUT/bench.json"

if [ "${SPHCONTACT_REPORT_SCENE:-1}" != 0 ]; then
    start=$(date +%s)
    # Snapshots are 603 MB each: the history and the summary are the figures.
    "$BIN" run scenes/large/disks_4m.toml --backend gpu --quiet --out "$OUT/disks_4m" \
        2>&1 | tee "$OUT/disks_4m.log"
    echo "wall time: $(($(date +%s) - start)) s" | tee -a "$OUT/disks_4m.log"
    rm -rf "$OUT/disks_4m/snapshots" "$OUT/disks_4m/snapshots.pvd"
fi
