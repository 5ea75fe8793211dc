//! Closed solids: meshes whose faces turned away from a camera outside them are never seen
//! (`BuildStats::closed_solid`, the lod baseline's [`closed_solid`]; docs/architecture.md, "Faces
//! turned away").

use std::collections::HashMap;

use super::{uf_find, uf_union};
use crate::hash::FxBuild;

/// Whether every edge-connected piece of `tris` (triangles joined across an edge between the
/// same two position ids; pieces that only touch at a point are apart) encloses a positive
/// volume, beyond rounding: its faces turn outwards. With every edge used once in each direction
/// ([`Level0`](super::dag)'s regular edges) this makes the triangles a closed solid, whose faces
/// turned away no ray from outside meets first, for pieces that do not pass through themselves
/// (a piece that does may hold a region turned inside out; scans and modelled solids do not). A
/// piece turned inwards (a room modelled from inside, a hollow's inner wall) or of no volume
/// (faces back to back) is refused; no triangles are none either.
pub(crate) fn positive_pieces(tris: &[[u32; 3]], pid: &[u32], pid_pos: &[[f32; 3]]) -> bool {
    use rayon::prelude::*;
    if tris.is_empty() {
        return false;
    }
    // Triangles joined by union-find across each undirected edge (sorted by its two ids).
    let mut edges: Vec<(u64, u32)> = tris
        .par_iter()
        .enumerate()
        .flat_map_iter(|(i, t)| {
            let p = t.map(|v| pid[v as usize] as u64);
            [(p[0], p[1]), (p[1], p[2]), (p[2], p[0])]
                .map(|(a, b)| (a.min(b) << 32 | a.max(b), i as u32))
        })
        .collect();
    edges.par_sort_unstable();
    let mut comp: Vec<u32> = (0..tris.len() as u32).collect();
    for w in edges.windows(2) {
        if w[0].0 == w[1].0 {
            uf_union(&mut comp, w[0].1, w[1].1);
        }
    }
    // Per piece (at its root triangle): the signed volume (six times, in f64, about the first
    // point of the mesh to keep the terms small) and the sum of the terms' magnitudes (the
    // scale of its rounding).
    let o = pid_pos[pid[tris[0][0] as usize] as usize].map(f64::from);
    let mut volume = vec![(0.0f64, 0.0f64); tris.len()];
    for (i, t) in tris.iter().enumerate() {
        let [a, b, c] = t.map(|v| {
            let x = pid_pos[pid[v as usize] as usize];
            [x[0] as f64 - o[0], x[1] as f64 - o[1], x[2] as f64 - o[2]]
        });
        let det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]);
        let e = &mut volume[uf_find(&mut comp, i as u32) as usize];
        e.0 += det;
        e.1 += det.abs();
    }
    (0..tris.len()).all(|i| {
        let (v, scale) = volume[i];
        comp[i] != i as u32 || v > scale * 1e-6
    })
}

/// Whether `indices` (triangles over `positions`) form a closed solid: vertices joined by equal
/// positions, triangles whose corners are not three distinct positions left out (they cover
/// nothing), every edge used once in each direction, and every edge-connected piece enclosing a
/// positive volume ([`positive_pieces`]). What the builder checks of its level 0, for a mesh as
/// imported (the lod baseline's levels).
pub fn closed_solid(positions: &[[f32; 3]], indices: &[u32]) -> bool {
    // Position ids by the coordinates' bits (-0 as +0).
    let key = |p: &[f32; 3]| p.map(|x| if x == 0.0 { 0 } else { x.to_bits() });
    let mut ids: HashMap<[u32; 3], u32, FxBuild> = HashMap::default();
    let mut pid_pos: Vec<[f32; 3]> = Vec::new();
    let pid: Vec<u32> = positions
        .iter()
        .map(|p| {
            *ids.entry(key(p)).or_insert_with(|| {
                pid_pos.push(*p);
                pid_pos.len() as u32 - 1
            })
        })
        .collect();
    let mut tris: Vec<[u32; 3]> = Vec::with_capacity(indices.len() / 3);
    for t in indices.chunks_exact(3) {
        if t.iter().any(|&v| v as usize >= positions.len()) {
            return false;
        }
        let p = [t[0], t[1], t[2]].map(|v| pid[v as usize]);
        if p[0] != p[1] && p[1] != p[2] && p[2] != p[0] {
            tris.push([t[0], t[1], t[2]]);
        }
    }
    // Every edge used once each way: the builder's own test of its level 0.
    super::dag::regular_edges(&tris, &pid, pid_pos.len()) && positive_pieces(&tris, &pid, &pid_pos)
}
