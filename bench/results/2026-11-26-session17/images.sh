#!/bin/bash
# Session 17, device (1920x1080, 1 px): each scene's lit image and the close blade's, H (main
# before, 233b13b) against N (the max-delta triangle code, triangles of several materials kept
# unrotated): pixels that differ and by how much (pngmax.py).
. bench/results/2026-11-26-session17/common.sh
o=$OUT/images.txt
setup $o H N
compare_images $o $D/pngmax.py
