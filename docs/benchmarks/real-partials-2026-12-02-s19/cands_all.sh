#!/bin/bash
# usage: cands_all.sh TAG [STRIDE]  (env passes through); only descriptor starts
D=/work/shared/datasets
for s in shrec16 shrec16_holes pfarm pfaust_m pfaust_h; do
  /work/main/target/release/examples/research_candidates $D/$s ${2:-1} 0 '{"centers":0,"plane_cuts":0}' > /work/runs/s19/cands-$1-$s.txt
done
python3 /work/runs/s19/merge_choose.py $1
