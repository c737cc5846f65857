#!/usr/bin/env bash
# Campaign speed (issue 26): 40 test points x 16 impact records (the seed rig's size), run as
# 40 separate `identify` processes (a lab's shell loop), and as one `campaign` with --jobs 1
# and --jobs 2. Prints the wall times and the ratios.
#   bash benches/campaign.sh            # records and plan under target/bench-campaign/
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --features cli --quiet
bin=target/release/bearing-ident
dir=target/bench-campaign
points=${POINTS:-40}
if [ ! -f "$dir/plan.toml" ]; then
  rm -rf "$dir"; mkdir -p "$dir"
  printf '[identify]\nband = [8.0, 49.0]\n[conditions]\nspeed = "rpm"\n' > "$dir/plan.toml"
  for p in $(seq 1 "$points"); do
    "$bin" simulate --kind impact --impacts 8 --noise 0.02 --seed "$p" --out "$dir/p$p" > /dev/null
    printf '[[point]]\nname = "p%s"\nfiles = "p%s/*.csv"\nspeed = %s\n' "$p" "$p" "$((p * 100))" >> "$dir/plan.toml"
  done
fi
now() { date +%s.%N; }
t0=$(now)
for p in $(seq 1 "$points"); do
  "$bin" identify --json --band 8,49 "$dir/p$p"/*.csv > /dev/null
done
t1=$(now)
"$bin" campaign "$dir/plan.toml" --jobs 1 > /dev/null
t2=$(now)
"$bin" campaign "$dir/plan.toml" --jobs 2 > /dev/null
t3=$(now)
python3 - "$t0" "$t1" "$t2" "$t3" "$points" <<'PY'
import sys
t0, t1, t2, t3, n = map(float, sys.argv[1:])
sep, j1, j2 = t1 - t0, t2 - t1, t3 - t2
print(f"{int(n)} points x 16 impact records")
print(f"  {int(n)} identify processes: {sep:6.2f} s")
print(f"  campaign --jobs 1:     {j1:6.2f} s  ({j1 / sep:.2f} x the processes)")
print(f"  campaign --jobs 2:     {j2:6.2f} s  ({j2 / sep:.2f} x the processes; {j1 / j2:.2f} x faster than --jobs 1)")
PY
