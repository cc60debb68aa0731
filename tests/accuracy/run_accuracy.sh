#!/bin/sh
# run_accuracy.sh SCENARIO MAPPER_YAML OUTDIR SF_SIM SF_MAPPER SF_EVAL PYTHON CHECK_BARS
# Simulates the scenario once, maps the log with every variant, scores the maps
# with the mapper's own config and checks the accuracy bars on report.json.
set -eu
scenario=$1 config=$2 out=$3 sim=$4 mapper=$5 eval=$6 python=$7 check=$8
mkdir -p "$out"
"$sim" --scenario "$scenario" --log "$out/run.lcmlog" --threads 1 --quiet
maps=""
for v in fls_only carve_only paper fused; do
  "$mapper" --config "$config" --log "$out/run.lcmlog" --map-out "$out/$v.map" --variant "$v" > "$out/$v.mapper.txt"
  maps="$maps --map $v=$out/$v.map"
done
# shellcheck disable=SC2086  # $maps is a list of options
"$eval" --scenario "$scenario" --config "$config" $maps --json "$out/report.json" --figures "$out/figures" --no-ply
"$python" "$check" "$scenario" "$out/report.json"
