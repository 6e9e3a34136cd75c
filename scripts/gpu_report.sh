#!/usr/bin/env bash
# The GPU report in one call, on a machine with a hardware GPU: a portable
# release build, the throughput bench with each integrator at 1e5, 1e6, 4e6
# and 1.6e7 particles (three measurements each, every stage timed alone and
# within real steps, the work of a step counted), then the four-million-
# particle disks and the penetration scene to their ends. Every figure
# lands in one folder:
#
#   scripts/gpu_report.sh [OUT]        (default: out/gpu_report)
#
#   OUT/adapter.txt          the adapters the solver sees, the GPU's own report
#   OUT/bench_midpoint.json  bench --backend gpu --repeat 3 --stages --json
#   OUT/bench_leapfrog.json  the same with --integrator leapfrog
#   OUT/disks_4m/            history.csv and summary.json of the 4e6 run
#   OUT/penetration/         those of scenes/penetration/tungsten_rod_steel_plate.toml
#   OUT/penetration_runs/    the same scene with both integrators, without snapshots
#                            and with one every 0.5 µs (scripts/penetration_runs.sh)
#   OUT/penetration_spread/  the same at Δx 0.1 mm, seven draws of each integrator
#                            (scripts/penetration_spread.sh)
#   OUT/<run>.log            each run's progress, with the wall time at the end
#
# SPHCONTACT_BIN=path skips the build and uses that binary instead (for a
# machine without a Rust toolchain). SPHCONTACT_REPORT_PARTICLES overrides
# the bench sizes (a size the device cannot hold is refused with the count
# that fits, and the report goes on); SPHCONTACT_REPORT_INTEGRATORS the
# integrators (default "midpoint leapfrog"); SPHCONTACT_REPORT_SCENE=0
# skips the scene runs.
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

PARTICLES=${SPHCONTACT_REPORT_PARTICLES:-100000 1000000 4000000 16000000}
for integrator in ${SPHCONTACT_REPORT_INTEGRATORS:-midpoint leapfrog}; do
    for n in $PARTICLES; do
        # One size a call, so that a size past the device's memory costs
        # only its own record.
        "$BIN" bench --backend gpu --particles "$n" --repeat 3 --stages --json \
            --integrator "$integrator" >"$OUT/bench_${integrator}_$n.json" \
            2>>"$OUT/bench.log" || echo "$integrator at $n: refused (bench.log)" | tee -a "$OUT/bench.log"
    done
    # The sizes' records in one list.
    python3 - "$OUT" "$integrator" $PARTICLES <<'PY' >"$OUT/bench_$integrator.json"
import json, os, sys
out, integrator, sizes = sys.argv[1], sys.argv[2], sys.argv[3:]
records = []
for n in sizes:
    path = os.path.join(out, f"bench_{integrator}_{n}.json")
    if os.path.getsize(path) > 0:
        records += json.load(open(path))
    os.remove(path)
print(json.dumps(records, indent=2))
PY
done

# A scene run to its end, timed: OUT/NAME/ and OUT/NAME.log.
run_scene() {
    local name=$1 scene=$2
    local start
    start=$(date +%s)
    "$BIN" run "$scene" --backend gpu --quiet --out "$OUT/$name" 2>&1 | tee "$OUT/$name.log" ||
        echo "$name: the run failed ($OUT/$name.log)"
    echo "wall time: $(($(date +%s) - start)) s" | tee -a "$OUT/$name.log"
    # Snapshots (603 MB each for the disks): the history and the summary
    # are the figures.
    rm -rf "$OUT/$name/snapshots" "$OUT/$name/snapshots.pvd"
}

if [ "${SPHCONTACT_REPORT_SCENE:-1}" != 0 ]; then
    run_scene disks_4m scenes/large/disks_4m.toml
    run_scene penetration scenes/penetration/tungsten_rod_steel_plate.toml
    SPHCONTACT_BIN="$BIN" scripts/penetration_runs.sh gpu "$OUT/penetration_runs" ||
        echo "penetration runs: failed ($OUT/penetration_runs)"
    SPHCONTACT_BIN="$BIN" scripts/penetration_spread.sh gpu "$OUT/penetration_spread" ||
        echo "penetration spread: failed ($OUT/penetration_spread)"
fi
