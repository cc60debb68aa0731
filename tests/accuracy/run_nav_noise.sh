#!/bin/sh
# run_nav_noise.sh CLEAN_SCENARIO NOISY_SCENARIO MAPPER_YAML OUTDIR SF_SIM SF_MAPPER SF_EVAL PYTHON CHECK
# Issue 11: the same reference scenario simulated with perfect NAV and with
# realistic NAV errors and vehicle motion, each mapped (fused) and scored
# against the true meshes; the check asserts that fused precision and visible
# recall of the noisy run are within 0.05 of the noise-free run.
set -eu
clean=$1 noisy=$2 config=$3 out=$4 sim=$5 mapper=$6 eval=$7 python=$8 check=$9
for run in clean noisy; do
  if [ "$run" = clean ]; then scenario=$clean; else scenario=$noisy; fi
  mkdir -p "$out/$run"
  "$sim" --scenario "$scenario" --log "$out/$run/run.lcmlog" --threads 1 --quiet
  "$mapper" --config "$config" --log "$out/$run/run.lcmlog" --map-out "$out/$run/fused.map" --variant fused \
      > "$out/$run/fused.mapper.txt"
  "$eval" --scenario "$scenario" --config "$config" --map "fused=$out/$run/fused.map" --log "$out/$run/run.lcmlog" \
      --json "$out/$run/report.json" --figures "$out/$run/figures" --no-ply
  rm -f "$out/$run/run.lcmlog"  # 44 MB each; the reports and figures stay
done
"$python" "$check" "$out/clean/report.json" "$out/noisy/report.json"
