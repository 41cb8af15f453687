#!/usr/bin/env bash
# Runs one libFuzzer target until it has used CPU_SECONDS of CPU time (not wall time: the machine is shared,
# and "an hour of fuzzing" means an hour of the fuzzer's own work). Never SIGSTOP a running fuzzer: its
# per-input -timeout is wall time, and a pause longer than that is reported as a timeout. Findings and the grown corpus stay in
# WORKDIR. Usage: scripts/fuzz-cpu.sh BUILD_FUZZ_DIR TARGET CORPUS_NAME CPU_SECONDS WORKDIR
set -euo pipefail
# With autogroup scheduling (Debian's default) nice only ranks tasks within one session: started
# without a terminal (setsid, nohup) it lowers its own session to nice 19, so builds and benchmarks
# keep the cores.
if [ "$(cat /proc/sys/kernel/sched_autogroup_enabled 2>/dev/null)" = 1 ] && ! tty -s; then
  echo 19 >/proc/self/autogroup 2>/dev/null || true
fi
build=$1 target=$2 corpus=$3 budget=$4 work=$5
src=$(cd "$(dirname "$0")/.." && pwd)/fuzz/corpus/$corpus
mkdir -p "$work/corpus-$corpus" "$work/artifacts-$corpus"
cp -n "$src"/* "$work/corpus-$corpus"/ 2>/dev/null || true
cd "$work"
nice -n 10 "$build/fuzz/$target" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
  -artifact_prefix="artifacts-$corpus/" "corpus-$corpus" >"log-$corpus.txt" 2>&1 &
pid=$!
ticks=$(getconf CLK_TCK)
cpu_seconds() { awk -v t="$ticks" '{print int(($14 + $15) / t)}' "/proc/$1/stat" 2>/dev/null || echo -1; }
used=0
while kill -0 "$pid" 2>/dev/null; do
  now=$(cpu_seconds "$pid")
  [ "$now" -ge 0 ] && used=$now
  if [ "$used" -ge "$budget" ]; then kill -INT "$pid"; break; fi
  sleep 5
done
status=0
wait "$pid" || status=$?
# libFuzzer exits 72 when SIGINT stops it (after its final stats); a finding leaves an artifact and another code.
echo "$target/$corpus: cpu_seconds=$used of $budget, exit=$status, artifacts=$(ls "artifacts-$corpus" | wc -l)" |
  tee -a summary.txt
