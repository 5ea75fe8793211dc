#!/bin/bash
# Session 17 (H100, 1920x1080, 1 px; call 8): the max-delta triangle code's vgeo figures with
# their errors against the supersampled reference (brute at 4x4 spp, box-filtered), N's code
# (.gpu/vgeo-N.gz, ae1fc13): session 16's script on that binary.
BIN=N bash bench/results/2026-11-26-session16/errors.sh
