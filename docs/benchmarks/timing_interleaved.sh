#!/usr/bin/env bash
# Same-run timing of two dualspectra binaries on SHREC'16 CUTS: the benches run interleaved,
# class by class, so both see the same machine load. Writes time.log (wall, user, sys per
# class and binary) and the bench JSON of each run in the current folder.
#   bash docs/benchmarks/timing_interleaved.sh OLD_BINARY NEW_BINARY [DATA]
set -u
old=$1; new=$2; data=${3:-${DUALSPECTRA_DATA:?set DUALSPECTRA_DATA or pass DATA}/shrec16}
for c in cat centaur david dog horse michael victoria wolf; do
  for v in old new; do
    bin=$old; [ "$v" = new ] && bin=$new
    /usr/bin/time -f "$v $c wall %e user %U sys %S" -a -o time.log \
      "$bin" bench "$data" --filter "_${c}_" --quiet --json "t-$v-$c.json" > "t-$v-$c.txt" 2>&1
  done
done
