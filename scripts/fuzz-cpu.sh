#!/usr/bin/env bash
# Runs one libFuzzer target until it has used CPU_SECONDS of CPU time (not wall time: the machine is shared,
# and "an hour of fuzzing" means an hour of the fuzzer's own work). Findings and the grown corpus stay in
# WORKDIR. Usage: scripts/fuzz-cpu.sh BUILD_FUZZ_DIR TARGET CORPUS_NAME CPU_SECONDS WORKDIR
set -euo pipefail
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
while kill -0 "$pid" 2>/dev/null; do
  used=$(cpu_seconds "$pid")
  if [ "$used" -ge "$budget" ]; then kill -INT "$pid"; break; fi
  sleep 5
done
status=0
wait "$pid" || status=$?
echo "$target/$corpus: cpu_seconds>=$budget exit=$status artifacts=$(ls "artifacts-$corpus" | wc -l)" | tee -a summary.txt
