#!/usr/bin/env bash
# How much of the penetration's residual velocity is round-off: the shipped
# scene (scenes/penetration/tungsten_rod_steel_plate.toml) at Δx = 0.1 mm
# (9,264 particles, to 30 µs), run with each integrator at several snapshot
# intervals. A snapshot ends the step that would cross it, so each interval
# moves every later step by round-off and the run is another draw of the
# same shot; the spread of the draws is the shot's own, and a difference
# between the integrators shows only where their means part by more than
# their scatter.
#
#   scripts/penetration_spread.sh cpu|gpu [OUT]   (default OUT: out/penetration_spread)
#
#   OUT/<backend>_<integrator>_<interval>/   each run's history.csv and summary.json
#   OUT/table_<backend>.md                   every run, then each integrator's mean,
#                                            standard deviation and range
#
# SPHCONTACT_BIN=path uses that binary instead of building one;
# SPHCONTACT_SPREAD_INTERVALS the intervals, s (0: no snapshots; default
# seven: "0 3e-7 5e-7 7e-7 9e-7 1.1e-6 1.3e-6"). On the CPU path a run takes
# one and a half to two and a half minutes on two cores.
set -euo pipefail
cd "$(dirname "$0")/.."
BACKEND=${1:?usage: scripts/penetration_spread.sh cpu|gpu [OUT]}
case "$BACKEND" in cpu | gpu) ;; *) echo "backend: cpu or gpu, not $BACKEND" >&2; exit 2 ;; esac
OUT=${2:-out/penetration_spread}
INTERVALS=${SPHCONTACT_SPREAD_INTERVALS:-0 3e-7 5e-7 7e-7 9e-7 1.1e-6 1.3e-6}
mkdir -p "$OUT"

BIN=${SPHCONTACT_BIN:-}
if [ -z "$BIN" ]; then
    cargo build --release --bin sphcontact
    BIN=target/release/sphcontact
fi

# The shipped scene with both bodies at 0.1 mm.
SCENE="$OUT/scene_0.1mm.toml"
sed 's/^spacing = 5.0e-5$/spacing = 1.0e-4/' scenes/penetration/tungsten_rod_steel_plate.toml >"$SCENE"
[ "$(grep -c '^spacing = 1.0e-4$' "$SCENE")" = 2 ] || {
    echo "the shipped scene no longer has two 'spacing = 5.0e-5' lines" >&2
    exit 1
}

for integrator in leapfrog midpoint; do
    for every in $INTERVALS; do
        name="${BACKEND}_${integrator}_${every}"
        "$BIN" run "$SCENE" --backend "$BACKEND" --integrator "$integrator" \
            --snapshot-every "$every" --quiet --out "$OUT/$name" >"$OUT/$name.log" 2>&1 ||
            echo "$name: the run failed ($OUT/$name.log)"
        rm -rf "$OUT/$name/snapshots" "$OUT/$name/snapshots.pvd"
    done
done

python3 - "$OUT" "$BACKEND" $INTERVALS <<'PY' | tee "$OUT/table_$BACKEND.md"
import json, os, statistics, sys
out, backend, intervals = sys.argv[1], sys.argv[2], sys.argv[3:]
print("| integrator | snapshots every (s) | status | steps | rod at the end (m/s) | total energy | out of range | plate failed |")
print("|---|---|---|---|---|---|---|---|")
speeds = {}
for integrator in ("leapfrog", "midpoint"):
    for every in intervals:
        path = os.path.join(out, f"{backend}_{integrator}_{every}", "summary.json")
        if not os.path.exists(path):
            print(f"| {integrator} | {every} | no summary | | | | | |")
            continue
        s = json.load(open(path))
        rod = next(b for b in s["bodies"] if b["name"] == "rod")
        plate = next(b for b in s["bodies"] if b["name"] == "plate")
        v = -rod["velocity_final"][1]
        if s["status"] == "completed":
            speeds.setdefault(integrator, []).append(v)
        print(
            f"| {integrator} | {every} | {s['status']} | {s['steps']:,} | {v:.1f} "
            f"| {100 * (s['energy_final'] / s['energy_initial'] - 1):+.3f} % "
            f"| {s['out_of_range']['count']} | {plate.get('failure', {}).get('failed', 0):,} |"
        )
print()
print("| integrator | runs | mean (m/s) | standard deviation | standard error of the mean | range |")
print("|---|---|---|---|---|---|")
groups = list(speeds.items()) + [("both", [v for vs in speeds.values() for v in vs])]
for name, vs in groups:
    if len(vs) < 2:
        continue
    m, sd = statistics.mean(vs), statistics.stdev(vs)
    print(f"| {name} | {len(vs)} | {m:.1f} | {sd:.2f} m/s ({100 * sd / m:.2f} %) "
          f"| {sd / len(vs) ** 0.5:.2f} m/s | {min(vs):.1f}–{max(vs):.1f} "
          f"({100 * (max(vs) - min(vs)) / min(vs):.2f} %) |")
PY
