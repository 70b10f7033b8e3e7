#!/bin/bash
D=/work/shared/datasets
for s in shrec16 shrec16_holes pfarm pfaust_m pfaust_h; do
  /work/main/target/release/examples/research_candidates $D/$s $1 > /work/runs/s19/vfull-$s.txt 2> /work/runs/s19/vfull-$s.err
done
