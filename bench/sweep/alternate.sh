#!/bin/bash
# Wall time of a command on 1 and 2 workers, side by side: PAIRS pairs, each
# the 1-worker run then the 2-worker run, a pair started only when the
# machine was at least 85 % idle over the 3 s before it (the project's
# machine is shared). WORKERS in the command is replaced by 1 or 2.
#   bench/sweep/alternate.sh 5 sweep40 target/release/ffr sweep bench/sweep/spin_up_40.toml --out /tmp/sweep --workers WORKERS
#   bench/sweep/alternate.sh 3 quick target/release/ffr report --quick --out /tmp/report --workers WORKERS
# Prints one line per run: label, pair, workers, wall (s), idle % before, load average, time.
pairs=$1; label=$2; shift 2
stat() { awk '/^cpu /{t=0; for(i=2;i<=NF;i++) t+=$i; print t, $5}' /proc/stat; }
idle() { read -r t1 i1 < <(stat); sleep 3; read -r t2 i2 < <(stat); echo $(( 100*(i2-i1)/(t2-t1) )); }
done=0; tries=0
while [ $done -lt $pairs ] && [ $tries -lt 300 ]; do
  tries=$((tries+1))
  id=$(idle)
  if [ "$id" -lt 85 ]; then continue; fi
  for w in 1 2; do
    cmd="${@//WORKERS/$w}"
    s=$(date +%s.%N); eval "$cmd" >/dev/null 2>&1; e=$(date +%s.%N)
    echo "$label pair $done workers $w wall $(echo "$e - $s" | bc) idle_before $id load1 $(cut -d' ' -f1 /proc/loadavg) $(date -u +%H:%M:%S)"
  done
  done=$((done+1))
done
echo "finished after $tries tries"
