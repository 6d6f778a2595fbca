#!/usr/bin/env bash
# Regenerates every benchmark CSV and chart of docs/benchmarks.md.
#
#   scripts/bench.sh [--build DIR] [--out DIR] [--tiny] [--only speed|stability|scaling|e2e]
#
# --build: a configured build tree (default build-bench; configured and built if missing).
# --out:   results folder (default bench-results); CSVs, logs and bench_*.png go there.
# --tiny:  a few-second smoke run of every driver (for CI): no charts, no e2e, no timings worth
#          reading.
# Needs gnuplot (scripts/install-deps.sh installs gnuplot-nox) and /usr/bin/time.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build-bench"
out="$root/bench-results"
tiny=0
only=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --tiny) tiny=1; shift ;;
    --only) only=$2; shift 2 ;;
    *) echo "bench.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
if [[ ! -f "$build/build.ninja" && ! -f "$build/Makefile" ]]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build" --target speed_accuracy stability scaling xtf_throughput sonarsynth_cli
mkdir -p "$out"
bin="$build/bench"
plots="$root/bench/plots"
want() { [[ -z "$only" || "$only" == "$1" ]]; }

if [[ $tiny == 1 ]]; then
  "$bin/speed_accuracy" --tiny --out "$out"
  "$bin/stability" --tiny --out "$out"
  "$bin/scaling" --tiny > "$out/scaling_tiny.csv"
  echo "bench.sh --tiny: ok ($out)"
  exit 0
fi

{
  echo "date: $(date -u +%FT%TZ)"
  echo "commit: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown) (working tree may differ)"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores"
  echo "memory: $(free -g | awk '/Mem:/ {print $2}') GiB"
  echo "kernel: $(uname -r)"
  echo "compiler: $(grep -m1 CMAKE_CXX_COMPILER: "$build/CMakeCache.txt" | cut -d= -f2) $(grep -m1 CMAKE_BUILD_TYPE: "$build/CMakeCache.txt" | cut -d= -f2)"
  echo "load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
} > "$out/machine.txt"

if want speed; then
  "$bin/speed_accuracy" --out "$out" --pings 10 --runs 15 --min-time 0.03 | tee "$out/speed_accuracy.log"
  for s in flat rough paper; do
    gnuplot -e "csv='$out/speed_accuracy_$s.csv'; png='$out/bench_speed_accuracy_$s.png'; ttl='Speed vs accuracy: $s scene (10 pings, median of 15 runs; Pareto front: times within 5 % tie)'" "$plots/speed_accuracy.gp"
  done
fi

if want stability; then
  "$bin/stability" --out "$out"
  gp() { gnuplot -e "csv='$out/stability_$1.csv'; png='$out/bench_stability_$1.png'; ttl='$2'; xl='$3'; logx=$4" "$plots/stability.gp"; }
  gp altitude "Flat seabed vs closed form: altitude" "altitude (m)" 1
  gp slope "Plane vs closed form: across-track slope (+ rises towards the side)" "slope (deg)" 0
  gp grazing "Flat seabed, 0.1 dB/m, 400 m range: error by grazing angle of the bin" "grazing angle (deg)" 1
  gp dem "Sinusoid terrain (8 m, 3.1 m) vs 2 mm DEM: DEM cell" "DEM cell (m)" 1
  gp object "Rock on flat seabed, pings every 0.2 m, vs 31 along-track planes: rock diameter" "rock diameter (m)" 1
  gp clearance "Pipe (0.5 m, 20 m out, 10 m down) as a closed section vs its circle: clearance" "clearance (diameters)" 0
  gp pipe_size "Pipe half a diameter up, 20 m out, vs its circle: diameter" "pipe diameter (m)" 1
  gp object_grazing "0.2 m pipe 40 m out, resting, vs its circle: grazing angle at the pipe" "grazing angle (deg)" 1
fi

if want scaling; then
  "$bin/scaling" samples --runs 3 --header | tee "$out/scaling_samples.csv"
  "$bin/scaling" objects --runs 3 --header | tee "$out/scaling_objects.csv"
  echo "cells,grid_mib,generate_s,pings,pings_per_s,peak_rss_mib" > "$out/scaling_grid.csv"
  for cells in 1e6 4e6 16e6 64e6 144e6 400e6; do
    "$bin/scaling" grid --cells "$cells" | tee -a "$out/scaling_grid.csv"
  done
  echo "lines,survey_m,pings,pings_per_s,peak_rss_mib" > "$out/scaling_length.csv"
  for lines in 1 2 4 8 16; do
    "$bin/scaling" length --lines "$lines" | tee -a "$out/scaling_length.csv"
  done
  gnuplot -e "dir='$out'" "$plots/scaling.gp"
fi

if want e2e; then
  # sonarsynth simulate on the paper scene (4 lines, XTF per line, mosaics), 2 threads, 3 runs
  # per variant; wall time and peak RSS from /usr/bin/time -v, stage split from the summary.
  cli="$build/tools/sonarsynth"
  echo "variant,run,wall_s,peak_rss_mib,pings,run_s,pings_per_s,profile_us,render_us,noise_us,mosaic_finish_s" > "$out/e2e.csv"
  for variant in full xtf-only; do
    extra=()
    [[ $variant == xtf-only ]] && extra=(--no-mosaic --no-waterfall --no-truth)
    for run in 1 2 3; do
      /usr/bin/time -v -o "$out/e2e_time.txt" "$cli" simulate "$root/samples/paper_pipes.yaml" \
        -o "$out/e2e_run" --overwrite --threads 2 "${extra[@]}" > "$out/e2e_stdout.txt" 2>&1
      wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {n=split($2,a,":"); s=0; for(i=1;i<=n;i++) s=s*60+a[i]; print s}' "$out/e2e_time.txt")
      rss=$(awk -F': ' '/Maximum resident set size/ {printf "%.1f", $2/1024}' "$out/e2e_time.txt")
      line=$(grep -m1 'pings on' "$out/e2e_stdout.txt")
      pings=$(sed -E 's/.*simulate: ([0-9]+) pings.*/\1/' <<< "$line")
      rphase=$(sed -E 's/.* written in ([0-9.]+) s \(.*/\1/' <<< "$line")
      rate=$(sed -E 's/.*\(([0-9]+) pings\/s end to end\).*/\1/' <<< "$line")
      cpu=$(grep -m1 'per ping, thread time' "$out/e2e_stdout.txt" | sed -E 's/.*profile ([0-9.]+) us, render ([0-9.]+) us, noise\+scaling ([0-9.]+) us.*/\1,\2,\3/')
      mos=$(grep -m1 'mosaic written' "$out/e2e_stdout.txt" | sed -E 's/.*in ([0-9.]+) s.*/\1/')
      echo "$variant,$run,$wall,$rss,$pings,$rphase,$rate,$cpu,${mos:-0}" | tee -a "$out/e2e.csv"
    done
  done
  rm -rf "$out/e2e_run"
  # The XTF write stage on its own: a file of the paper survey's size (8,004 pings of 2 x 4096
  # u16 samples) written and read back, median of 5 runs.
  "$bin/xtf_throughput" 8004 4096 5 | tee "$out/e2e_xtf.txt"
fi
# Markdown tables of every CSV (pasted into docs/benchmarks.md).
{
  for s in flat rough paper; do
    f="$out/speed_accuracy_$s.csv"
    [[ -f $f ]] || continue
    echo "#### speed vs accuracy: $s"
    a="$out/auto_planes_$s.csv"
    [[ -f $a ]] && awk -F, 'NR>1 {printf "Default along-track planes (auto): %s, estimated error %.3g dB (tolerance %s dB) from %s pilot pings in %.1f ms.\n\n", $2, $3, $4, $5, $6}' "$a"
    echo "| method | planes | ms/ping | time IQR | RMS dB (all lit bins) | RMS dB (interior) | worst dB (interior) | RMS dB (edge) | empty | Pareto (5 %) | Pareto (strict) | default |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|:-:|:-:|:-:|"
    awk -F, 'NR>1 {printf "| %s | %s | %.3f | %.0f %% | %.3g | %.3g | %.3g | %.3g | %.3f | %s | %s | %s |\n", $3, $7, $11, 100*$24, $22, $12, $13, $14, $16, ($18?"x":""), ($23?"x":""), ($19?"x":"")}' "$f"
    echo
  done
  for w in altitude slope grazing dem object clearance pipe_size object_grazing; do
    f="$out/stability_$w.csv"
    [[ -f $f ]] || continue
    echo "#### stability: $w (RMS dB / worst dB / empty fraction)"
    awk -F, 'NR>1 {k=$2; if(!(k in seen)){seen[k]=1; xs[++nx]=k} if(!($4 in ls)){ls[$4]=1; lb[++nl]=$4} v[k,$4]=sprintf("%.3g / %.3g / %.2f",$5,$6,$9)}
      END {printf "| x |"; for(j=1;j<=nl;j++) printf " %s |", lb[j]; printf "\n|---|"; for(j=1;j<=nl;j++) printf "---|"; printf "\n";
           for(i=1;i<=nx;i++){printf "| %s |", xs[i]; for(j=1;j<=nl;j++) printf " %s |", v[xs[i],lb[j]]; printf "\n"}}' "$f"
    echo
  done
  if [[ -f "$out/e2e_xtf.txt" ]]; then
    echo "#### e2e_xtf (xtf_throughput 8004 4096 5)"
    echo '```'
    cat "$out/e2e_xtf.txt"
    echo '```'
    echo
  fi
  for f in scaling_samples scaling_objects scaling_grid scaling_length e2e; do
    [[ -f "$out/$f.csv" ]] || continue
    echo "#### $f"
    awk -F, 'NR==1 {printf "|"; for(i=1;i<=NF;i++) printf " %s |", $i; printf "\n|"; for(i=1;i<=NF;i++) printf "---|"; printf "\n"; next}
             {printf "|"; for(i=1;i<=NF;i++) printf " %s |", $i; printf "\n"}' "$out/$f.csv"
    echo
  done
} > "$out/tables.md"
echo "bench.sh: results in $out (tables in $out/tables.md)"
