#!/bin/bash
# usage: starts_all.sh TAG  (env passes through)
D=/work/shared/datasets
for s in shrec16 shrec16_holes pfarm pfaust_m pfaust_h; do
  /work/main/target/release/examples/research_starts $D/$s 1 > /work/runs/s19/starts-$1-$s.txt
done
python3 /work/runs/s19/starts_sum.py $1
