#!/bin/bash
# Run here (not on the device) before next.sh: the shader folders it carries in .gpu/, made from
# git and this folder's diffs. shA-C: f0ec5ef's shaders_glsl as they are (a control: compiled at
# start-up, as the others); shA-V / shA-P: the same with session 42's V (row 0 first) and P
# (mesh_partial() false) applied; shM-P: 4164bda's with P.
set -e
R=bench/results/2026-11-28-session42
mk() { # DIR COMMIT [DIFF]
  rm -rf .gpu/$1 && mkdir -p .gpu/$1
  git archive $2 shaders_glsl | tar x -C .gpu/$1 --strip-components=1
  if [ -n "$3" ]; then patch -s -d .gpu/$1 -p1 < $3; fi
}
mk shA-C f0ec5ef
mk shA-V f0ec5ef $R/call2/sh-V.diff
mk shA-P f0ec5ef $R/call3/sh-P.diff
mk shM-P 4164bda $R/call3/sh-P.diff
ls -d .gpu/sh[AM]-*
