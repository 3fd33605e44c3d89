#!/usr/bin/env bash
# The main job: installs what is missing, builds, bakes the default material set, reproduces the
# paper's Fig. 2, plots every model, measures speed against error, renders every default material in
# POV-Ray, Blender and Mitsuba against brdf eval, measures what each material mode costs in the
# renderer, renders the model comparisons, and writes a report (index.html) that opens with a
# one-screen summary and ends with the time of each stage.
#
# Usage: ./run.sh [--small] [--out DIR] [--no-build]
#   --small     reduced sizes (coarser grids, smaller bakes and renders; what the test runs)
#   --out DIR   report directory (default: out/report)
#   --no-build  skip installing packages and building; use $BRDF_EXE (default build/cli/brdf)
# Expected duration (stated when it starts): ~10 min on a fresh two-core machine (7m33s measured
# before the cost stage, 5m13s of it installing and building; `--no-build` 7m08s with it, the cost
# stage 2m45s); `--small --no-build` 3m38s-4m05s with the cost stage (48 s; shared machine).
# Progress (numbered stages with elapsed times) goes to stderr; each stage's own output goes to
# DIR/logs/. A failed stage does not stop the later ones (except install/build); the job exits 1
# at the end naming every failed stage.
set -uo pipefail
root=$(cd "$(dirname "$0")" && pwd)
out="$root/out/report"
small=0
build=1
while (($#)); do
  case "$1" in
    --small) small=1 ;;
    --out) [[ $# -ge 2 ]] || { echo "run.sh: --out needs a directory" >&2; exit 2; }; out=$2; shift ;;
    --out=*) out=${1#--out=} ;;
    --no-build) build=0 ;;
    -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    *) echo "run.sh: unknown option '$1' (see ./run.sh --help)" >&2; exit 2 ;;
  esac
  shift
done
mkdir -p "$out/logs" || exit 1
out=$(cd "$out" && pwd)
py=/usr/bin/python3
small_flag=()
((small)) && small_flag=(--small)
if ((build)); then brdf="$root/build/cli/brdf"; else brdf=${BRDF_EXE:-$root/build/cli/brdf}; fi

# ---------------------------------------------------------------- progress display
job_start=$EPOCHREALTIME
timings="$out/timings.csv"
echo "stage,title,status,seconds,log" >"$timings"
failed=()
stage_no=0
stage_total=13

seconds_since() { awk -v a="$1" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.1f", b - a }'; }
human() {  # 75.3 -> 1m15s, 8.25 -> 8.2 s
  awk -v s="$1" 'BEGIN { if (s < 60) printf "%.1f s", s; else printf "%dm%02ds", int(s / 60), int(s) % 60 }'
}
last_line() { tail -n 1 "$1" 2>/dev/null | tr -d '\r' | cut -c1-"$2"; }
csv_field() { printf '"%s"' "${1//\"/\'}"; }  # one quoted CSV field

# run_stage NAME TITLE FUNCTION [ARGS...]: runs FUNCTION with its output in logs/NN-NAME.log,
# shows a live timer (and the stage's latest output line) on a terminal, records the timing.
run_stage() {
  local name=$1 title=$2
  shift 2
  stage_no=$((stage_no + 1))
  local log="$out/logs/$(printf %02d "$stage_no")-$name.log"
  local start=$EPOCHREALTIME
  printf '[%d/%d] %s\n' "$stage_no" "$stage_total" "$title" >&2
  ("$@") >"$log" 2>&1 &
  local pid=$! beat=0
  if [[ -t 2 ]]; then
    local width=$(( ${COLUMNS:-$(tput cols 2>/dev/null || echo 100)} - 18 ))
    while kill -0 "$pid" 2>/dev/null; do
      printf '\r\033[K      %8s  %s' "$(human "$(seconds_since "$start")")" "$(last_line "$log" "$width")" >&2
      sleep 0.5
    done
    printf '\r\033[K' >&2
  else
    while kill -0 "$pid" 2>/dev/null; do  # a heartbeat every 30 s for logs
      sleep 0.2
      beat=$((beat + 1))
      ((beat % 150 == 0)) && printf '      %s: %s\n' "$(human "$(seconds_since "$start")")" "$(last_line "$log" 100)" >&2
    done
  fi
  wait "$pid"
  local status=$?
  local took
  took=$(seconds_since "$start")
  if ((status == 0)); then
    printf '      ok in %s (job %s)\n' "$(human "$took")" "$(human "$(seconds_since "$job_start")")" >&2
    echo "$stage_no,$(csv_field "$title"),ok,$took,logs/${log##*/}" >>"$timings"
  else
    printf '      FAILED after %s: %s\n      log: %s\n' "$(human "$took")" "$(last_line "$log" 200)" "$log" >&2
    echo "$stage_no,$(csv_field "$title"),$(csv_field "FAILED: $(last_line "$log" 300)"),$took,logs/${log##*/}" >>"$timings"
    failed+=("$stage_no ($name)")
  fi
  return "$status"
}
skip_stage() {
  stage_no=$((stage_no + 1))
  printf '[%d/%d] %s: skipped (%s)\n' "$stage_no" "$stage_total" "$1" "$2" >&2
  echo "$stage_no,$(csv_field "$1"),$(csv_field "skipped: $2"),0," >>"$timings"
}

# ---------------------------------------------------------------- stages
need_subcommand() {  # need_subcommand NAME: fails with one line when `brdf NAME` does not exist
  if ! "$brdf" --help 2>/dev/null | grep -Eq "^ +$1( |\$)"; then
    echo "missing piece: \`brdf $1\` is not available in $brdf (not implemented yet?)"
    return 1
  fi
}
need_script() {
  if [[ ! -f "$root/$1" ]]; then
    echo "missing piece: $1 does not exist (not implemented yet?)"
    return 1
  fi
}

stage_install() { "$root/scripts/install_deps.sh" --with-renderers; }
# The Python module too: the report's scripts take their numbers from it (tools/report/brdfcli.py),
# and building it here keeps it from lagging behind a rebuilt brdf. With the add-on's zip, the build
# holds everything `cmake --install build` installs (the README's quickstart).
stage_build() { "$root/scripts/build.sh" "$root/build" brdf libbrdf_python libbrdf_blender_addon; }
stage_bake() {
  need_subcommand bake || return 1
  "$py" "$root/tools/report/bake_materials.py" --brdf "$brdf" --out "$out/bakes" "${small_flag[@]}"
}
stage_fig2() { "$py" "$root/tools/report/fig2.py" --brdf "$brdf" --out "$out" "${small_flag[@]}"; }
stage_models() { "$py" "$root/tools/report/model_plots.py" --brdf "$brdf" --out "$out" "${small_flag[@]}"; }
stage_albedo() {
  need_subcommand albedo || return 1
  "$py" "$root/tools/report/albedo.py" --brdf "$brdf" --out "$out" "${small_flag[@]}"
}
stage_bench() {
  need_subcommand bench || return 1
  "$brdf" bench --out "$out" --quick
}
stage_summary() {
  need_script tools/render_summary.py || return 1
  "$py" "$root/tools/render_summary.py" --brdf "$brdf" --out "$out/renders" "${small_flag[@]}"
}
# Blender 4.5 LTS (bpy from PyPI, scripts/python_env.sh bpy45); Debian's Blender where that venv
# cannot be made (exit 3: no Python 3.11 or no package index).
stage_cost() {
  need_script tools/bench/renderer_cost.py || return 1
  local blender=4.5
  "$root/scripts/python_env.sh" bpy45 >/dev/null
  case $? in
    0) ;;
    3) blender=debian; echo "bpy 4.5 unavailable: Cycles timed in Debian's Blender" ;;
    *) return 1 ;;
  esac
  "$py" "$root/tools/bench/renderer_cost.py" --brdf "$brdf" --out "$out/cost" --blender "$blender" "${small_flag[@]}"
}
stage_povray() {
  need_script tools/render_povray_comparison.py || return 1
  "$py" "$root/tools/render_povray_comparison.py" --brdf "$brdf" --out "$out/renders" "${small_flag[@]}"
}
stage_blender() {
  need_script tools/render_blender_comparison.py || return 1
  "$py" "$root/tools/render_blender_comparison.py" --brdf "$brdf" --out "$out/renders" "${small_flag[@]}"
}
stage_fitscene() {
  need_script tools/render_fit_scene.py || return 1
  "$py" "$root/tools/render_fit_scene.py" --brdf "$brdf" --out "$out/renders" "${small_flag[@]}"
}
stage_index() {
  "$py" "$root/tools/report/make_index.py" --out "$out" --brdf "$brdf" "${small_flag[@]}"
}

mode="full size"
((small)) && mode="reduced size (--small)"
printf 'libbrdf main job, %s -> %s\n' "$mode" "$out" >&2
# Measured on two-core machines: a fresh full-size run took 7m33s before the cost stage, 5m13s of
# it installing and building; `--no-build` 7m08s with the cost stage (2m45s of it; load 4-6);
# `--small --no-build` 3m38s and 4m05s (shared machine, load 4-6).
if ((build)); then
  expected="~12 min on a fresh two-core machine (~5 min of it the install and build; less when build/ is up to date; the first run also makes the pinned PyPI venvs)"
  ((small)) && expected="the install and build (~5 min when fresh) plus ~2-5 min"
else
  expected="~7 min on two cores"
  ((small)) && expected="~2-5 min on two cores"
fi
printf 'expected duration: %s\n' "$expected" >&2
if ((build)); then
  run_stage install "Install missing Debian packages (scripts/install_deps.sh --with-renderers)" stage_install ||
    { echo "run.sh: cannot continue without the packages" >&2; exit 1; }
  run_stage build "Build libbrdf, the brdf CLI and the Python module (scripts/build.sh)" stage_build ||
    { echo "run.sh: cannot continue without a build" >&2; exit 1; }
else
  skip_stage "Install missing Debian packages" "--no-build"
  skip_stage "Build libbrdf and the brdf CLI" "--no-build"
fi
if [[ ! -x "$brdf" ]]; then
  echo "run.sh: no brdf executable at $brdf (build first, or set BRDF_EXE)" >&2
  exit 1
fi
run_stage bake "Bake the default material set (brdf bake)" stage_bake
run_stage fig2 "Reproduce the paper's Fig. 2 (R_d maps)" stage_fig2
run_stage models "Plot every model in-plane, polar and over the hemisphere" stage_models
run_stage albedo "Directional albedo (white furnace) of every model, both K modes (brdf albedo)" stage_albedo
run_stage bench "Speed against error (brdf bench --quick)" stage_bench
run_stage summary "Every default material in POV-Ray, Blender and Mitsuba, one exposure, against brdf eval" stage_summary
run_stage cost "What each material mode costs in Cycles and POV-Ray (tools/bench/renderer_cost.py)" stage_cost
run_stage povray "POV-Ray comparison renders" stage_povray
run_stage blender "Blender comparison renders" stage_blender
run_stage fitscene "FIT materials in a scene: sky + two suns, Blender and POV-Ray side by side" stage_fitscene
run_stage index "Write the report (index.html)" stage_index
# Once more so that the report lists the index stage's own time too (takes well under a second).
stage_index >>"$out/logs/$(printf %02d "$stage_no")-index.log" 2>&1

total=$(seconds_since "$job_start")
if ((${#failed[@]})); then
  printf 'run.sh: %d stage(s) failed: %s (total %s). Report: %s/index.html\n' \
    "${#failed[@]}" "${failed[*]}" "$(human "$total")" "$out" >&2
  exit 1
fi
printf 'run.sh: done in %s. Report: %s/index.html\n' "$(human "$total")" "$out" >&2
