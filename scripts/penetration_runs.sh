#!/usr/bin/env bash
# The shipped penetration scene (scenes/penetration/tungsten_rod_steel_plate.toml,
# Δx = 50 µm, 37,024 particles, to 30 µs) on one backend with both
# integrators, without snapshots and with one every 0.5 µs (which ends the
# steps that would cross them, so the four runs differ in round-off), then
# one table of what docs/hard_cases.md ("Penetration") compares across them:
#
#   scripts/penetration_runs.sh cpu|gpu [OUT]     (default OUT: out/penetration_runs)
#
#   OUT/<backend>_<integrator>_<snapshots>/   each run's outputs (the snapshots,
#                                             about 0.4 GB a run, removed after it)
#   OUT/<backend>_<integrator>_<snapshots>.log  its closing line and wall time
#   OUT/table_<backend>.md                    the table
#
# SPHCONTACT_BIN=path uses that binary instead of building one. On the CPU
# path a run takes half an hour or more on two cores; on a data-centre GPU
# well under a minute.
set -euo pipefail
cd "$(dirname "$0")/.."
BACKEND=${1:?usage: scripts/penetration_runs.sh cpu|gpu [OUT]}
case "$BACKEND" in cpu | gpu) ;; *) echo "backend: cpu or gpu, not $BACKEND" >&2; exit 2 ;; esac
OUT=${2:-out/penetration_runs}
SCENE=scenes/penetration/tungsten_rod_steel_plate.toml
mkdir -p "$OUT"

BIN=${SPHCONTACT_BIN:-}
if [ -z "$BIN" ]; then
    cargo build --release --bin sphcontact
    BIN=target/release/sphcontact
fi

for integrator in leapfrog midpoint; do
    for every in 0 5e-7; do
        name="${BACKEND}_${integrator}_$([ "$every" = 0 ] && echo none || echo every_0.5us)"
        start=$(date +%s)
        "$BIN" run "$SCENE" --backend "$BACKEND" --integrator "$integrator" \
            --snapshot-every "$every" --quiet --out "$OUT/$name" >"$OUT/$name.log" 2>&1 ||
            echo "$name: the run failed ($OUT/$name.log)"
        echo "wall time: $(($(date +%s) - start)) s" >>"$OUT/$name.log"
        rm -rf "$OUT/$name/snapshots" "$OUT/$name/snapshots.pvd"
    done
done

python3 - "$OUT" "$BACKEND" <<'PY' | tee "$OUT/table_$BACKEND.md"
import json, os, sys
out, backend = sys.argv[1], sys.argv[2]
print("| run | status | steps | rod at the end (m/s) | total energy | ledger residual | out of range | plate failed | most debris | wall (s) |")
print("|---|---|---|---|---|---|---|---|---|---|")
speeds = []
for integrator in ("leapfrog", "midpoint"):
    for snaps in ("none", "every_0.5us"):
        name = f"{backend}_{integrator}_{snaps}"
        path = os.path.join(out, name, "summary.json")
        if not os.path.exists(path):
            print(f"| {name} | no summary | | | | | | | | |")
            continue
        s = json.load(open(path))
        e0 = s["energy_initial"]
        rod = next(b for b in s["bodies"] if b["name"] == "rod")
        plate = next(b for b in s["bodies"] if b["name"] == "plate")
        v = -rod["velocity_final"][1]
        if s["status"] == "completed":
            speeds.append(v)
        print(
            f"| {name} | {s['status']}, {s['time_reached'] * 1e6:.2f} µs | {s['steps']:,} | {v:.1f} "
            f"| {100 * (s['energy_final'] / e0 - 1):+.3f} % (spring loss {s['energy_spring_loss']:+.0f} J) "
            f"| {s['energy']['residual'] / e0:+.1e} | {s['out_of_range']['count']} "
            f"| {plate.get('failure', {}).get('failed', 0):,} | {s['debris']['max']} | {s['wall_seconds']:.0f} |"
        )
if len(speeds) > 1:
    print(f"\nrod speeds of the completed runs: {min(speeds):.1f}–{max(speeds):.1f} m/s, "
          f"spread {100 * (max(speeds) - min(speeds)) / min(speeds):.2f} % of the lowest")
PY
