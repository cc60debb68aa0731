#!/bin/sh
# run_window_change.sh FIXED_SCENARIO CHANGED_SCENARIO MAPPER_YAML OUTDIR SF_SIM SF_MAPPER SF_EVAL PYTHON CHECK
# Issue 14, per-ping FLS geometry: the reference scenario simulated with a fixed
# FLS range window and with the window zoomed mid-run (fls.window_changes), each
# mapped (fused) and scored; the changed log is also mapped with
# fls.max_geometries 1 (per-ping geometry off), which must refuse the zoomed
# frames, so the change really happened. The check asserts fused precision and
# visible recall of the changed run within 0.05 of the fixed run.
set -eu
fixed=$1 changed=$2 config=$3 out=$4 sim=$5 mapper=$6 eval=$7 python=$8 check=$9
mkdir -p "$out"
"$python" - "$config" "$out/one_geometry.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c.setdefault("fls", {})["max_geometries"] = 1
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
for run in fixed changed; do
  if [ "$run" = fixed ]; then scenario=$fixed; else scenario=$changed; fi
  mkdir -p "$out/$run"
  "$sim" --scenario "$scenario" --log "$out/$run/run.lcmlog" --threads 1 --quiet
  "$mapper" --config "$config" --log "$out/$run/run.lcmlog" --map-out "$out/$run/fused.map" --variant fused \
      > "$out/$run/fused.mapper.txt"
  if [ "$run" = changed ]; then
    "$mapper" --config "$out/one_geometry.yaml" --log "$out/$run/run.lcmlog" --map-out "$out/$run/one.map" \
        --variant fused > "$out/$run/one_geometry.mapper.txt"
  fi
  "$eval" --scenario "$scenario" --config "$config" --map "fused=$out/$run/fused.map" \
      --json "$out/$run/report.json" --figures "$out/$run/figures" --no-ply
  rm -f "$out/$run/run.lcmlog"
done
"$python" "$check" "$out"
