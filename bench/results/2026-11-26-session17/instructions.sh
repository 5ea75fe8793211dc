#!/bin/bash
# Session 17, this machine: the build's work counted in instructions (valgrind's callgrind:
# deterministic where this machine's timings vary by 15 %), issue 11's base 217d124 against
# main, one thread, per scan: the whole command, the builder (`dag::build_inner`, what the build's
# `seconds` time) and meshoptimizer's simplifier inside it.
# BASE=/work/base/target/release/vgeo MAIN=target/release/vgeo bash instructions.sh
for m in bunny lucy turbineblade; do
  for b in base main; do
    bin=$BASE; [ $b = main ] && bin=$MAIN
    f=/tmp/cg-$b-$m.out
    valgrind --tool=callgrind --callgrind-out-file=$f $bin build ../shared/assets/scanned/$m.ply -o /tmp/cg.vgeo --threads 1 > /dev/null 2>&1
    bi=$(callgrind_annotate --inclusive=yes $f | grep -E "dag::build_inner \[" | head -1 | awk '{print $1}')
    ms=$(callgrind_annotate --inclusive=yes $f | grep -E "\(.*meshopt_simplifyWithAttributes \[" | head -1 | awk '{print $1}')
    tot=$(callgrind_annotate $f | grep "PROGRAM TOTALS" | awk '{print $1}')
    echo "$m $b command $tot build_inner $bi meshopt_simplifyWithAttributes $ms"
  done
done
