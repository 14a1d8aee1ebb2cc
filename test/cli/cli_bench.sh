#!/usr/bin/env bash
# `mcvio bench --quick` end to end: 2 scenarios x 2 modes at feature level, the report files exist
# and hold sane measured numbers, progress lines per run, bad options exit 2 naming the option; a
# tiny image-level run finds the pedestrian's clean floor.
set -u
mcvio=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0
. "$(dirname "$0")/expect.sh"
fail() { echo "FAIL: $*"; failed=1; }

out=$("$mcvio" bench --quick --out "$tmp/bench" 2>"$tmp/err")
rc=$?
[ "$rc" -eq 0 ] || { fail "bench --quick exited $rc"; cat "$tmp/err"; }
for f in bench.json bench.md ate_by_scenario.png rpe_by_scenario.png; do
  [ -s "$tmp/bench/$f" ] || fail "missing or empty $f"
done
grep -qF "## Targets" <<<"$out" || fail "no target table printed"
grep -qE "^\| elevator_s1 \| auto \| [0-9]+/501 \| [0-9.]+ \|" <<<"$out" || fail "no elevator auto row: $out"
grep -qF "## Elevator ride" <<<"$out" || fail "no elevator ride table"
[ "$(grep -cE '^\[[1-4]/4\] ' "$tmp/err")" -eq 4 ] || fail "want 4 progress lines: $(cat "$tmp/err")"
python3 - "$tmp/bench/bench.json" <<'PY' || fail "bench.json numbers"
import json, math, sys
j = json.load(open(sys.argv[1]))
seqs = j["sequences"]
assert [s["name"] for s in seqs] == ["none_s1", "elevator_s1"], [s["name"] for s in seqs]
for s in seqs:
    assert s["frames"] == 501, s["frames"]
    assert [r["mode"] for r in s["runs"]] == ["reference", "auto"]
    for r in s["runs"]:
        assert r["tracked_frames"] > 250, r
        for k in ("ate_posyaw_rmse_m", "ate_se3_rmse_m", "rpe_translation_rmse_m", "cpu_median_ms"):
            assert r[k] is not None and 0 < r[k] < 100, (s["name"], r["mode"], k, r[k])
        d = r["detection"]
        assert d["tp"] + d["fp"] + d["tn"] + d["fn"] == r["tracked_frames"], d
        assert 0 <= d["fpr"] <= 1
    ref = s["runs"][0]["vs_reference"]
    assert ref["ate_reduction_percent"] == 0 and ref["rpe_reduction_percent"] == 0, ref
    assert s["runs"][1]["checks"]["cost"] is not None
none, elev = seqs
assert none["conflict_frames"] == 0 and elev["conflict_frames"] > 100, (none["conflict_frames"], elev["conflict_frames"])
assert none["runs"][1]["detection"]["tpr"] is None  # no positives on the clean sequence
ride = elev["runs"][1]["ride"]
assert ride["truth_dz_m"] > 10 and ride["estimate_dz_m"] is not None, ride
assert elev["runs"][1]["checks"]["ride_displacement"] is not None
modes = {t["mode"] for t in j["targets"]}
assert modes == {"auto"}, modes
PY
[ "$failed" -eq 0 ] && echo "ok: quick suite report"

# Image level, tiny: the pedestrian is rendered along the clean office's trajectory with its IMU, so
# the office's reference run is its clean floor.
out=$("$mcvio" bench --level images --scenarios none,pedestrian --modes reference,auto --sequence-duration 8 \
      --onset 3 --conflict-duration 3 --out "$tmp/bi" 2>"$tmp/err_bi")
rc=$?
[ "$rc" -eq 0 ] || { fail "bench --level images exited $rc"; cat "$tmp/err_bi"; }
grep -qF "## Clean floor" <<<"$out" || fail "no clean floor section: $out"
[ "$(grep -cE '^\[[1-4]/4\] ' "$tmp/err_bi")" -eq 4 ] || fail "want 4 image-level progress lines: $(cat "$tmp/err_bi")"
python3 - "$tmp/bi/bench.json" <<'PY' || fail "image-level bench.json clean floor"
import json, sys
seqs = {s["name"]: s for s in json.load(open(sys.argv[1]))["sequences"]}
none, ped = seqs["none_s1"], seqs["pedestrian_s1"]
assert none["clean_floor_ate_posyaw_m"] is None, none["clean_floor_ate_posyaw_m"]
floor = ped["clean_floor_ate_posyaw_m"]
assert floor is not None and floor == none["runs"][0]["ate_posyaw_rmse_m"], (floor, none["runs"][0])
PY
[ "$failed" -eq 0 ] && echo "ok: image-level clean floor"

expect 2 "must include 'reference'" -- "$mcvio" bench --quick --modes imu,auto --out "$tmp/x"
expect 2 "tornado" -- "$mcvio" bench --quick --scenarios none,tornado --out "$tmp/x"
expect 2 "sweep_scenarios" -- "$mcvio" bench --quick --duration-sweep 0,10 --sweep-scenarios pedestrian --out "$tmp/x"
expect 2 "nothing to run" -- "$mcvio" bench --scenarios "" --no-sweep --out "$tmp/x"
expect 2 "need --level images" -- "$mcvio" bench --quick --real "$tmp" --out "$tmp/x"
expect 2 "--calib and --texture-filter need --level images" -- "$mcvio" bench --quick --texture-filter anisotropic --out "$tmp/x"
expect 2 "$tmp/no_rig: no such folder (the rig to render with" -- "$mcvio" bench --level images --scenarios none --calib "$tmp/no_rig" --out "$tmp/x"
help=$("$mcvio" bench --help)
for o in --out --level --modes --scenarios --seeds --duration-sweep --no-sweep --sweep-scenarios --sequence-duration \
         --onset --conflict-duration --sweep-tail --rpe-delta-s --jobs --quick --oracle-track-labels --no-plots --semi-real \
         --real --overlay-onset --overlay-duration --config Examples; do
  grep -qF -- "$o" <<<"$help" || fail "--help lacks $o"
done
exit "$failed"
