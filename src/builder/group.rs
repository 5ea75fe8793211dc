//! Grouping clusters with METIS on the cluster graph (weight = shared boundary edges, plus
//! low-weight proximity edges between clusters adjacent in Morton order).

use super::cluster::{Graph, morton_chain_edges, morton_codes, partition};

/// Partitions clusters (each given by its triangles in global vertex indices, and its centre) into
/// groups of at most `group_max`, aiming for `target` clusters per group. Returns indices into
/// `clusters` per group, each sorted.
pub(crate) fn group_clusters(
    clusters: &[&[[u32; 3]]],
    centers: &[[f32; 3]],
    pid: &[u32],
    target: usize,
    group_max: usize,
) -> Vec<Vec<u32>> {
    let n = clusters.len();
    if n <= group_max {
        return vec![(0..n as u32).collect()];
    }
    let mut keyed: Vec<(u64, u32)> = Vec::new();
    for (ci, tris) in clusters.iter().enumerate() {
        for tri in tris.iter() {
            for e in 0..3 {
                let a = pid[tri[e] as usize];
                let b = pid[tri[(e + 1) % 3] as usize];
                let (a, b) = if a < b { (a, b) } else { (b, a) };
                keyed.push(((a as u64) << 32 | b as u64, ci as u32));
            }
        }
    }
    keyed.sort_unstable();
    keyed.dedup();
    let mut edges: Vec<(u32, u32, i32)> = Vec::new();
    let mut i = 0;
    while i < keyed.len() {
        let mut j = i + 1;
        while j < keyed.len() && keyed[j].0 == keyed[i].0 {
            j += 1;
        }
        let run = &keyed[i..j];
        if run.len() <= 8 {
            for x in 0..run.len() {
                for y in x + 1..run.len() {
                    edges.push((run[x].1, run[y].1, 4));
                }
            }
        } else {
            for w in run.windows(2) {
                edges.push((w[0].1, w[1].1, 4));
            }
        }
        i = j;
    }
    let codes = morton_codes(centers);
    morton_chain_edges(&codes, 1, &mut edges);
    let g = Graph::from_edges(n, &edges);
    let fits = |p: &[u32]| p.len() <= group_max;
    partition(&g, &codes, target, group_max, &fits)
}
