#!/usr/bin/env bash
# Writes the committed seed corpus of the `input` target (corpus/input/): every bundled and
# example scenario as text, and bundled names with `--set` overrides that reach the other
# branches of Case::new (laws, schemes, models, repeated cars, viaduct keys, probes).
# Input shape (src/lib.rs): TEXT, then NUL and one `--set` per line. The `[support]` seeds name
# records/quake.csv (written here: one period of a sine on x and two on z, ending at rest),
# relative to this directory, where .ci/fuzz runs the target.
set -euo pipefail
cd "$(dirname "$0")"
out=corpus/input
rm -rf "$out"
mkdir -p "$out"
for f in ../sim/scenarios/*.toml ../sim/scenarios/examples/*.toml; do
  cp "$f" "$out/text-$(basename "$f" .toml)"
done
mkdir -p records
awk 'BEGIN { print "t_s,ax_m_per_s2,ay_m_per_s2,az_m_per_s2";
  pi = atan2(0, -1);
  for (j = 0; j <= 100; j++) { t = j * 0.005;
    printf "%.3f,%.17e,0,%.17e\n", t, 0.5 * sin(2 * pi * t / 0.5), 0.3 * sin(4 * pi * t / 0.5) } }' \
  >records/quake.csv
seed() { # NAME SCENARIO SET...
  local name=$1 scenario=$2
  shift 2
  { printf '%s\0' "$scenario"; printf '%s\n' "$@"; } >"$out/set-$name"
}
state='controller.state={kp_V_per_m=51600.0, kd_V_s_per_m=1600.0, ka_V_s2_per_m=40.0, ki_V_per_m_s=4300.0, kc_V_per_A=10.0, vmax_V=500.0}'
seed gap-loop paper-4.2 law=gap-loop
seed state paper-4.2 law=state geometry=ems vehicle.wheel_mass_kg=1000 "$state"
seed modal paper-4.2 model=modal modes=20 speed=150
seed accurate paper-4.2 scheme=accurate nsub=8 alpha=0.25 controller.interp=parabolic
seed repeat paper-4.2 vehicle.repeat=3 vehicle.car_length_m=25 t_end=2 dt=0.002
seed probes paper-4.2 'output.probes=["span1.midspan.rx", "wheel4.gap_y", "car1.body.z"]'
seed no-irregularity paper-4.2 irregularity.enabled=false seed=7 model=rigid
seed wheel-rail paper-5 train.kind=wheel-rail train.cars=2 'output.probes=["wheel1.force_z"]'
seed maglev-state paper-5 train.cars=4 elements=8 law=state geometry=ems "$state" train.wheel_mass_kg=500
seed quake-wave paper-5-quake support.spatial=wave-passage support.apparent_speed_m_per_s=400 support.synthetic.duration_s=5 support.synthetic.strong_end_s=4
seed settled paper-5-settled support.settlement.1.dz_m=-0.02 support.settlement.1.pier=2 train.cars=4
seed viaduct paper-5 bridge.pier.elements=8 soil.poisson=0.3 bridge.bearings.drop_m=0
seed ground paper-5 "ground.distances_m=[12.5, 25.0]" ground.pier=20 soil.damping_ratio=0.05
seed forces train-forces train.repeat=4 train.car_length_m=30 train.offset_y_m=1
seed moving-force moving-force model=modal vehicle.force_kN=-100 'bridge.spans_m=[20, 30]'
seed record paper-5 support.record=records/quake.csv train.cars=4
seed record-wave paper-5 support.record=records/quake.csv support.spatial=wave-passage support.apparent_speed_m_per_s=300
seed records paper-5 'bridge.spans_m=[30.0, 30.0]' 'support.records=["records/quake.csv", "records/quake.csv", "records/quake.csv"]' 'output.probes=["pier2.base.z"]'
seed record-spans moving-force support.record=records/quake.csv model=modal
seed state-keys paper-4.2 law=state geometry=ems vehicle.wheel_mass_kg=1000 controller.state.kp_V_per_m=51600 controller.state.kd_V_s_per_m=1600 controller.state.ka_V_s2_per_m=40 controller.state.ki_V_per_m_s=4300 controller.state.kc_V_per_A=10 controller.state.vmax_V=500 controller.state.rate_Hz=5000 controller.state.observer_Hz=200
seed state-design unit controller.state.vmax_V=400 controller.state.rate_Hz=2000 controller.state.observer_Hz=100 controller.state.design=true
