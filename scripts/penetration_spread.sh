#!/usr/bin/env bash
# How much of the penetration's residual velocity is round-off, and how
# much is the time step: the shipped scene
# (scenes/penetration/tungsten_rod_steel_plate.toml) at Δx = 0.1 mm (9,264
# particles, to 30 µs), run with each integrator at several snapshot
# intervals. A snapshot ends the step that would cross it, so each interval
# moves every later step by round-off and the run is another draw of the
# same shot; the spread of the draws is the shot's own, and a difference
# between the integrators, or between two steps, shows only where their
# means part by more than their scatter.
#
#   scripts/penetration_spread.sh cpu|gpu [OUT]   (default OUT: out/penetration_spread)
#
#   OUT/<backend>_<integrator>_cfl<C>_<interval>/   each run's history.csv and summary.json
#   OUT/table_<backend>.md                           every run, then each integrator's and
#                                                    step's mean, standard deviation and range
#
# SPHCONTACT_BIN=path uses that binary instead of building one;
# SPHCONTACT_SPREAD_INTERVALS the intervals, s (0: no snapshots; default
# seven: "0 3e-7 5e-7 7e-7 9e-7 1.1e-6 1.3e-6"); SPHCONTACT_SPREAD_SPACING
# both bodies' spacing, m (default 1.0e-4; the shipped 5.0e-5 takes about
# twenty times as long); SPHCONTACT_SPREAD_CFLS the Courant numbers, each
# a set of draws (default 0.3, the scene's); SPHCONTACT_SPREAD_JOBS how
# many runs at once (default 1, with every thread; more: one thread each,
# which for these small scenes gets more runs through the same cores). On
# the CPU path a run at 0.1 mm and CFL 0.3 takes one and a half to two and
# a half minutes on two cores; at 0.2 mm, about 25 s on one thread.
set -euo pipefail
cd "$(dirname "$0")/.."
BACKEND=${1:?usage: scripts/penetration_spread.sh cpu|gpu [OUT]}
case "$BACKEND" in cpu | gpu) ;; *) echo "backend: cpu or gpu, not $BACKEND" >&2; exit 2 ;; esac
OUT=${2:-out/penetration_spread}
INTERVALS=${SPHCONTACT_SPREAD_INTERVALS:-0 3e-7 5e-7 7e-7 9e-7 1.1e-6 1.3e-6}
SPACING=${SPHCONTACT_SPREAD_SPACING:-1.0e-4}
CFLS=${SPHCONTACT_SPREAD_CFLS:-0.3}
JOBS=${SPHCONTACT_SPREAD_JOBS:-1}
mkdir -p "$OUT"

BIN=${SPHCONTACT_BIN:-}
if [ -z "$BIN" ]; then
    cargo build --release --bin sphcontact
    BIN=target/release/sphcontact
fi

# The shipped scene with both bodies at SPACING, one copy a Courant number.
SHIPPED=scenes/penetration/tungsten_rod_steel_plate.toml
[ "$(grep -c '^spacing = 5.0e-5$' "$SHIPPED")" = 2 ] &&
    [ "$(grep -c '^\[simulation\]$' "$SHIPPED")" = 1 ] &&
    ! grep -q '^cfl' "$SHIPPED" || {
    echo "$SHIPPED no longer has two 'spacing = 5.0e-5' lines, one [simulation] and no cfl" >&2
    exit 1
}
for cfl in $CFLS; do
    sed -e "s/^spacing = 5.0e-5$/spacing = $SPACING/" -e "s/^\[simulation\]$/[simulation]\ncfl = $cfl/" \
        "$SHIPPED" >"$OUT/scene_cfl$cfl.toml"
done

# One run: integrator, Courant number, snapshot interval.
one() {
    local name="${BACKEND}_$1_cfl$2_$3"
    local threads=()
    [ "$JOBS" -gt 1 ] && threads=(env RAYON_NUM_THREADS=1)
    "${threads[@]}" "$BIN" run "$OUT/scene_cfl$2.toml" --backend "$BACKEND" --integrator "$1" \
        --snapshot-every "$3" --quiet --out "$OUT/$name" >"$OUT/$name.log" 2>&1 ||
        echo "$name: the run failed ($OUT/$name.log)"
    rm -rf "$OUT/$name/snapshots" "$OUT/$name/snapshots.pvd"
}
for integrator in leapfrog midpoint; do
    for cfl in $CFLS; do
        for every in $INTERVALS; do
            one "$integrator" "$cfl" "$every" &
            while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n; done
        done
    done
done
wait

python3 - "$OUT" "$BACKEND" "$CFLS" $INTERVALS <<'PY' | tee "$OUT/table_$BACKEND.md"
import json, os, statistics, sys
out, backend, cfls, intervals = sys.argv[1], sys.argv[2], sys.argv[3].split(), sys.argv[4:]
print("| integrator | CFL | snapshots every (s) | status | steps | rod at the end (m/s) | total energy | out of range | plate failed |")
print("|---|---|---|---|---|---|---|---|---|")
speeds, failed = {}, {}
for integrator in ("leapfrog", "midpoint"):
    for cfl in cfls:
        for every in intervals:
            path = os.path.join(out, f"{backend}_{integrator}_cfl{cfl}_{every}", "summary.json")
            if not os.path.exists(path):
                print(f"| {integrator} | {cfl} | {every} | no summary | | | | | |")
                continue
            s = json.load(open(path))
            rod = next(b for b in s["bodies"] if b["name"] == "rod")
            plate = next(b for b in s["bodies"] if b["name"] == "plate")
            v = -rod["velocity_final"][1]
            n_failed = plate.get("failure", {}).get("failed", 0)
            if s["status"] == "completed":
                speeds.setdefault((integrator, cfl), []).append(v)
                failed.setdefault((integrator, cfl), []).append(n_failed)
            print(
                f"| {integrator} | {cfl} | {every} | {s['status']} | {s['steps']:,} | {v:.1f} "
                f"| {100 * (s['energy_final'] / s['energy_initial'] - 1):+.3f} % "
                f"| {s['out_of_range']['count']} | {n_failed:,} |"
            )
print()
print("| integrator | CFL | runs | mean (m/s) | standard deviation | standard error of the mean | range | plate failed (mean) |")
print("|---|---|---|---|---|---|---|---|")
for (name, cfl), vs in speeds.items():
    if len(vs) < 2:
        continue
    m, sd = statistics.mean(vs), statistics.stdev(vs)
    print(f"| {name} | {cfl} | {len(vs)} | {m:.1f} | {sd:.2f} m/s ({100 * sd / m:.2f} %) "
          f"| {sd / len(vs) ** 0.5:.2f} m/s | {min(vs):.1f}–{max(vs):.1f} "
          f"({100 * (max(vs) - min(vs)) / min(vs):.2f} %) | {statistics.mean(failed[(name, cfl)]):.0f} |")
PY
