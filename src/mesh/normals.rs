//! Vertex normals for meshes that come without them: smooth within a crease angle, split at creases.
//!
//! A glTF viewer or a DCC tool shades a mesh without normals smoothly across gentle bends and flat
//! across sharp edges (a box's faces, a turbine blade's rim). Averaging every face around a vertex
//! instead bends the shading of whole faces towards their neighbours, which is wrong at full detail
//! and worse once the builder simplifies the mesh. [`crease_normals`] marks an edge *sharp* where
//! its two faces meet at more than the crease angle, splits the faces around each position into
//! *smooth fans* (faces joined across edges that are not sharp, as Blender's auto-smooth does), and
//! gives every corner the angle-weighted average normal of its fan. A vertex is split only where
//! sharp edges cut its fan apart, so a curved surface without creases keeps one vertex per position
//! however coarse its triangles. The splits are attribute seams: the builder keeps them
//! (meshoptimizer does not collapse across a seam), so a crease stays sharp at every level of detail.
//!
//! (Comparing each corner's face with every face around it instead, as some viewers do, is not
//! transitive: on a coarse curved scan the faces around a vertex differ by more than the crease
//! angle from end to end, every corner got a slightly different normal, and Lucy's 50 K vertices
//! became 151 K seam vertices that the simplifier must keep.)

use std::collections::HashMap;

use super::Mesh;
use crate::hash::FxBuild;

/// Default crease angle in degrees (faces meeting at a sharper angle are shaded apart).
pub const DEFAULT_CREASE_DEG: f32 = 60.0;

fn sub(a: [f32; 3], b: [f32; 3]) -> [f64; 3] {
    [
        a[0] as f64 - b[0] as f64,
        a[1] as f64 - b[1] as f64,
        a[2] as f64 - b[2] as f64,
    ]
}

fn cross(u: [f64; 3], w: [f64; 3]) -> [f64; 3] {
    [
        u[1] * w[2] - u[2] * w[1],
        u[2] * w[0] - u[0] * w[2],
        u[0] * w[1] - u[1] * w[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalized(a: [f64; 3]) -> Option<[f64; 3]> {
    let len = dot(a, a).sqrt();
    (len.is_finite() && len > 1e-300).then(|| [a[0] / len, a[1] / len, a[2] / len])
}

/// Whether a stored normal is usable (finite, not zero).
fn usable(n: [f32; 3]) -> bool {
    let len = (n[0] as f64).hypot(n[1] as f64).hypot(n[2] as f64);
    len.is_finite() && len > 1e-20
}

/// Root of `i` in a union-find, halving paths as it goes.
fn find(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let up = parent[parent[i as usize] as usize];
        parent[i as usize] = up;
        i = up;
    }
    i
}

/// Joins the sets of `a` and `b` (the smaller root becomes the root).
fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
}

/// Normalizes every usable normal; vertices without one (zero or not finite) get crease-angle
/// normals: an edge is sharp where its faces' normals differ by more than `crease_deg` degrees,
/// the faces around a *position* (any vertex there, so UV or material splits do not matter) fall
/// into smooth fans joined across edges that are not sharp, and each triangle corner gets the
/// angle-weighted average normal of its fan. A vertex whose corners get different normals is split
/// (new vertices appended, indices updated). `crease_deg >= 180` shades smoothly everywhere, `0`
/// flat per face. Linear in the corners (a counting sort by position; each position on its own, in
/// parallel). Deterministic. Returns how many vertices were added.
pub fn crease_normals(mesh: &mut Mesh, crease_deg: f32) -> usize {
    let n = mesh.positions.len();
    mesh.normals.resize(n, [0.0; 3]);
    let mut need = vec![false; n];
    for (v, nn) in mesh.normals.iter_mut().enumerate() {
        if usable(*nn) {
            let len = (nn[0] as f64).hypot(nn[1] as f64).hypot(nn[2] as f64);
            *nn = nn.map(|c| (c as f64 / len) as f32);
        } else {
            need[v] = true;
        }
    }
    if !need.iter().any(|&x| x) {
        return 0;
    }
    let tri_count = mesh.indices.len() / 3;
    // Position ids (bit-equal positions share one) and, per position, the triangles around it.
    let mut pos_id: HashMap<[u32; 3], u32, FxBuild> =
        HashMap::with_capacity_and_hasher(n, FxBuild::default());
    let pid: Vec<u32> = mesh
        .positions
        .iter()
        .map(|p| {
            let next = pos_id.len() as u32;
            *pos_id.entry(p.map(f32::to_bits)).or_insert(next)
        })
        .collect();
    let npos = pos_id.len();
    drop(pos_id);
    // A corner's position id (an index out of range reads as a position of its own, `npos`).
    let corner_pid = |c: usize| -> u32 {
        pid.get(mesh.indices[c] as usize)
            .copied()
            .unwrap_or(npos as u32)
    };
    // Per corner its position id; per face its unit normal (zero where degenerate), per corner
    // its angle (the weight). A corner's two edge directions are the face's unit edge vectors,
    // one of them negated (exactly the normalized difference taken the other way).
    use rayon::prelude::*;
    let cpid: Vec<u32> = (0..tri_count * 3).into_par_iter().map(corner_pid).collect();
    let mut face_normal = vec![[0.0f64; 3]; tri_count];
    let mut weight = vec![0.0f64; tri_count * 3];
    let (indices, positions) = (&mesh.indices, &mesh.positions);
    face_normal
        .par_iter_mut()
        .zip(weight.par_chunks_mut(3))
        .enumerate()
        .with_min_len(4096)
        .for_each(|(t, (normal, w))| {
            let p: [[f32; 3]; 3] = std::array::from_fn(|k| {
                let i = indices[3 * t + k] as usize;
                positions.get(i).copied().unwrap_or([0.0; 3])
            });
            *normal = normalized(cross(sub(p[1], p[0]), sub(p[2], p[0]))).unwrap_or([0.0; 3]);
            // Edge k runs from corner k to corner k + 1.
            let e: [Option<[f64; 3]>; 3] =
                std::array::from_fn(|k| normalized(sub(p[(k + 1) % 3], p[k])));
            for k in 0..3 {
                let (a, b) = (e[k], e[(k + 2) % 3].map(|v| v.map(|x| -x)));
                w[k] = match (a, b) {
                    (Some(a), Some(b)) => dot(a, b).clamp(-1.0, 1.0).acos(),
                    _ => 0.0,
                };
            }
        });
    let cos_crease = if crease_deg >= 180.0 {
        -2.0
    } else {
        (crease_deg.max(0.0) as f64).to_radians().cos() - 1e-9
    };
    // Corners grouped by position (a counting sort, so each position's corners stay in corner
    // order). Fans never span positions: each position's fans are found and summed on their own,
    // in parallel over blocks of positions.
    let mut start = vec![0u32; npos + 2];
    for &p in &cpid {
        start[p as usize + 1] += 1;
    }
    for i in 0..=npos {
        start[i + 1] += start[i];
    }
    let mut by_pos = vec![0u32; tri_count * 3];
    {
        let mut fill = start.clone();
        for (c, &p) in cpid.iter().enumerate() {
            let slot = &mut fill[p as usize];
            by_pos[*slot as usize] = c as u32;
            *slot += 1;
        }
    }
    // Each corner's normal, in `by_pos` order: blocks of whole positions, each with its slice.
    let mut fan_normal = vec![[0.0f32; 3]; tri_count * 3];
    let mut blocks: Vec<(usize, usize, &mut [[f32; 3]])> = Vec::new();
    {
        const BLOCK_CORNERS: u32 = 1 << 14;
        let mut rest: &mut [[f32; 3]] = &mut fan_normal;
        let mut p0 = 0;
        for p in 1..=npos + 1 {
            if p == npos + 1 || start[p] - start[p0] >= BLOCK_CORNERS {
                let (head, tail) =
                    std::mem::take(&mut rest).split_at_mut((start[p] - start[p0]) as usize);
                blocks.push((p0, p, head));
                rest = tail;
                p0 = p;
            }
        }
    }
    let input = FanInput {
        cpid: &cpid,
        face_normal: &face_normal,
        weight: &weight,
        cos_crease,
    };
    blocks.into_par_iter().for_each(|(p0, p1, out)| {
        let mut scratch = FanScratch::default();
        let base = start[p0] as usize;
        for p in p0..p1 {
            let (a, b) = (start[p] as usize, start[p + 1] as usize);
            input.position_fans(
                p as u32,
                &by_pos[a..b],
                &mut scratch,
                &mut out[a - base..b - base],
            );
        }
    });
    drop((start, face_normal, weight, cpid));
    let mut corner_normal = vec![[0.0f32; 3]; tri_count * 3];
    for (&c, &n) in by_pos.iter().zip(&fan_normal) {
        corner_normal[c as usize] = n;
    }
    drop((by_pos, fan_normal));
    // Vertices split per distinct normal, in corner order.
    let mut split: HashMap<(u32, [u32; 3]), u32, FxBuild> = HashMap::default();
    let mut first_normal: Vec<Option<[u32; 3]>> = vec![None; n];
    let mut added = 0usize;
    for (c, &normal) in corner_normal.iter().enumerate() {
        let v = mesh.indices[c] as usize;
        if !need.get(v).copied().unwrap_or(false) {
            continue;
        }
        let bits = normal.map(f32::to_bits);
        match first_normal[v] {
            None => {
                first_normal[v] = Some(bits);
                mesh.normals[v] = normal;
            }
            Some(b) if b == bits => {}
            Some(_) => {
                let id = *split.entry((v as u32, bits)).or_insert_with(|| {
                    mesh.positions.push(mesh.positions[v]);
                    mesh.normals.push(normal);
                    let uv = mesh.uvs.get(v).copied().unwrap_or([0.0; 2]);
                    mesh.uvs.push(uv);
                    added += 1;
                    (mesh.positions.len() - 1) as u32
                });
                mesh.indices[c] = id;
            }
        }
    }
    added
}

/// What the smooth fans of a position are found from: per corner its position id (`cpid`) and
/// angle (`weight`), per face its unit normal.
struct FanInput<'a> {
    cpid: &'a [u32],
    face_normal: &'a [[f64; 3]],
    weight: &'a [f64],
    /// Faces meet smoothly where their normals' dot product is at least this.
    cos_crease: f64,
}

/// Reused buffers of [`FanInput::position_fans`].
#[derive(Default)]
struct FanScratch {
    /// (the other position of an edge at this position, local corner)
    edges: Vec<(u32, u32)>,
    /// Union-find over the local corners (a set's root is its smallest corner).
    parent: Vec<u32>,
    /// Per fan root: the fan's weighted normal sum, then its unit normal.
    sum: Vec<[f64; 3]>,
    unit: Vec<Option<[f64; 3]>>,
}

/// A position with more edge entries than this pairs them by a sort, fewer by a scan.
const SCAN_EDGES: usize = 32;

impl FanInput<'_> {
    /// The normals of the corners at position `p` (`corners`, ascending), into `out` (one per
    /// corner): faces join across an edge from `p` whose faces meet smoothly (every smooth pair
    /// of a non-manifold edge); a degenerate face's edges that stay at `p` join their corners, as
    /// a fan around `p` would (their normals are zero, so only at a crease of 90 degrees or more).
    /// Each fan's normal is the angle-weighted sum of its faces' normals in corner order; a corner
    /// whose fan sums to nothing takes its face's normal, else +z.
    fn position_fans(&self, p: u32, corners: &[u32], s: &mut FanScratch, out: &mut [[f32; 3]]) {
        let next = |c: u32| c - c % 3 + (c + 1) % 3;
        let prev = |c: u32| c - c % 3 + (c + 2) % 3;
        // A corner at `p` by its index in `corners` (the corners after and before a corner of a
        // degenerate edge at `p` are at `p` too).
        let local = |c: u32, or: u32| corners.binary_search(&c).map_or(or, |i| i as u32);
        s.parent.clear();
        s.parent.extend(0..corners.len() as u32);
        s.edges.clear();
        let mut first_degenerate = None;
        for (i, &c) in corners.iter().enumerate() {
            let i = i as u32;
            let (to, from) = (self.cpid[next(c) as usize], self.cpid[prev(c) as usize]);
            if to == p {
                if 0.0 >= self.cos_crease {
                    union(&mut s.parent, i, local(next(c), i));
                    union(&mut s.parent, i, *first_degenerate.get_or_insert(i));
                }
            } else {
                s.edges.push((to, i));
            }
            if from != p {
                s.edges.push((from, i));
            }
        }
        // Corners whose edges from `p` end at the same other position, and whose faces meet
        // smoothly, join: every such pair (all pairs of a non-manifold edge). A fan's handful of
        // entries is paired by a scan, a huge fan's by a sort.
        let smooth = |i: u32, j: u32| {
            let (a, b) = (corners[i as usize] / 3, corners[j as usize] / 3);
            dot(self.face_normal[a as usize], self.face_normal[b as usize]) >= self.cos_crease
        };
        if s.edges.len() <= SCAN_EDGES {
            for (x, &(q, i)) in s.edges.iter().enumerate() {
                for &(r, j) in &s.edges[x + 1..] {
                    if q == r && smooth(i, j) {
                        union(&mut s.parent, i, j);
                    }
                }
            }
        } else {
            s.edges.sort_unstable();
            for run in s.edges.chunk_by(|a, b| a.0 == b.0) {
                for (x, &(_, i)) in run.iter().enumerate() {
                    for &(_, j) in &run[x + 1..] {
                        if smooth(i, j) {
                            union(&mut s.parent, i, j);
                        }
                    }
                }
            }
        }
        // Each fan's sum over its corners in ascending order (its root, the smallest, first).
        let k = corners.len();
        s.sum.clear();
        s.sum.resize(k, [0.0; 3]);
        s.unit.clear();
        s.unit.resize(k, None);
        for (i, &c) in corners.iter().enumerate() {
            let root = find(&mut s.parent, i as u32) as usize;
            let c = c as usize;
            let n = self.face_normal[c / 3];
            for (a, n) in s.sum[root].iter_mut().zip(n) {
                *a += n * self.weight[c];
            }
        }
        for (i, (&c, out)) in corners.iter().zip(out.iter_mut()).enumerate() {
            let root = find(&mut s.parent, i as u32) as usize;
            if root == i {
                s.unit[i] = normalized(s.sum[i]);
            }
            let c = c as usize;
            *out = s.unit[root]
                .or(normalized(self.face_normal[c / 3]))
                .unwrap_or([0.0, 0.0, 1.0])
                .map(|x| x as f32);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube with 8 shared corners and no normals.
    fn cube() -> Mesh {
        let mut m = Mesh {
            name: "cube".into(),
            materials: vec![super::super::Material::default()],
            ..Default::default()
        };
        for i in 0..8u32 {
            m.positions
                .push([(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32]);
        }
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        for q in quads {
            m.indices.extend([q[0], q[1], q[2], q[0], q[2], q[3]]);
            m.material_ids.extend([0, 0]);
        }
        m.normals = vec![[0.0; 3]; 8];
        m.uvs = vec![[0.0; 2]; 8];
        m
    }

    #[test]
    fn a_cube_is_shaded_flat_below_90_degrees_and_smooth_above() {
        let mut flat = cube();
        let added = crease_normals(&mut flat, 60.0);
        // Each corner is shared by 3 faces at 90 degrees: 3 vertices per corner.
        assert_eq!(added, 16);
        assert_eq!(flat.positions.len(), 24);
        flat.validate().expect("valid");
        // Every corner's normal is its face's normal.
        for tri in flat.indices.chunks_exact(3) {
            let p: [[f32; 3]; 3] = std::array::from_fn(|k| flat.positions[tri[k] as usize]);
            let fnormal = normalized(cross(sub(p[1], p[0]), sub(p[2], p[0]))).expect("area");
            for &i in tri {
                let nn = flat.normals[i as usize].map(f64::from);
                assert!(dot(nn, fnormal) > 0.9999, "{nn:?} vs {fnormal:?}");
            }
        }
        let mut smooth = cube();
        assert_eq!(crease_normals(&mut smooth, 120.0), 0);
        // Corner (0,0,0) points away from the centre along the diagonal.
        let n0 = smooth.normals[0].map(f64::from);
        let d = normalized([-1.0, -1.0, -1.0]).expect("diag");
        assert!(dot(n0, d) > 0.999, "{n0:?}");
    }

    #[test]
    fn existing_normals_are_kept_and_normalized() {
        let mut m = cube();
        m.normals = vec![[0.0, 0.0, 2.0]; 8];
        assert_eq!(crease_normals(&mut m, 60.0), 0);
        assert!(m.normals.iter().all(|n| *n == [0.0, 0.0, 1.0]));
    }

    /// A cone of `k` faces around an apex, without normals.
    fn cone(k: u32) -> Mesh {
        let mut m = Mesh {
            name: "cone".into(),
            materials: vec![super::super::Material::default()],
            ..Default::default()
        };
        m.positions.push([0.0, 0.0, 1.0]);
        for i in 0..k {
            let a = std::f32::consts::TAU * i as f32 / k as f32;
            m.positions.push([a.cos(), a.sin(), 0.0]);
        }
        for i in 0..k {
            m.indices.extend([0, 1 + i, 1 + (i + 1) % k]);
            m.material_ids.push(0);
        }
        m.normals = vec![[0.0; 3]; m.positions.len()];
        m.uvs = vec![[0.0; 2]; m.positions.len()];
        m
    }

    /// Regression: a fan of many triangles around one position cost the square of their number
    /// (80,000 took 15 s to import). Smooth fans are found by a sort, so a huge fan is cheap and
    /// shaded like any other: smoothly at 180 degrees (one apex normal, straight up).
    #[test]
    fn a_huge_fan_is_cheap_and_smooth() {
        let mut m = cone(80_000);
        let t0 = std::time::Instant::now();
        let added = crease_normals(&mut m, 180.0);
        m.validate().expect("valid");
        assert_eq!(added, 0);
        let apex = m.normals[0].map(f64::from);
        assert!(apex[2] > 0.9999, "{apex:?}");
        // Generous: the quadratic version took 15 s in release; this one takes milliseconds.
        assert!(t0.elapsed().as_secs_f64() < 5.0, "{:?}", t0.elapsed());
    }

    /// A smooth curved surface whose faces around a vertex differ by more than the crease angle
    /// from end to end, but by little across each edge, keeps one vertex per position: only
    /// sharp edges split. (Comparing each corner's face with every face around it split every
    /// corner of such a vertex.)
    #[test]
    fn a_coarse_smooth_cone_is_not_split() {
        // 12 faces around a steep apex: neighbours differ by ~29 degrees, opposite faces by ~160.
        let mut m = cone(12);
        for p in m.positions.iter_mut().skip(1) {
            p[0] *= 0.1;
            p[1] *= 0.1;
        }
        let added = crease_normals(&mut m, 60.0);
        assert_eq!(added, 0, "no edge is sharper than 60 degrees");
        let apex = m.normals[0].map(f64::from);
        assert!(apex[2] > 0.99, "{apex:?}");
        // With a crease below the neighbour angle every edge is sharp: flat, each apex corner apart.
        let mut flat = cone(12);
        for p in flat.positions.iter_mut().skip(1) {
            p[0] *= 0.1;
            p[1] *= 0.1;
        }
        assert!(crease_normals(&mut flat, 20.0) > 0);
    }

    /// A fin: two coplanar faces and a third at 90 degrees on the same edge (non-manifold), plus
    /// a degenerate face at one of the edge's ends. Below 90 degrees the coplanar pair share
    /// their normals along the edge and the fin keeps its own (each end of the edge split once);
    /// above, the fin joins them (no split).
    #[test]
    fn a_non_manifold_fin_is_split_from_its_coplanar_pair() {
        let mut m = Mesh {
            name: "fin".into(),
            materials: vec![super::super::Material::default()],
            ..Default::default()
        };
        // Edge 0-1 on the x axis; faces in the z = 0 plane on either side, a fin going up in z.
        m.positions = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [0.5, -1.0, 0.0],
            [0.5, 0.0, 1.0],
        ];
        m.indices = vec![0, 1, 2, 1, 0, 3, 0, 1, 4, 0, 0, 1];
        m.material_ids = vec![0; 4];
        m.normals = vec![[0.0; 3]; 5];
        m.uvs = vec![[0.0; 2]; 5];
        let mut sharp = m.clone();
        assert_eq!(crease_normals(&mut sharp, 60.0), 2);
        sharp.validate().expect("valid");
        // The coplanar faces' corners at the edge point along z, the fin's along -y.
        let corner = |m: &Mesh, c: usize| m.normals[m.indices[c] as usize].map(f64::from);
        for c in [0, 1, 3, 4] {
            assert!(
                corner(&sharp, c)[2].abs() > 0.9999,
                "{:?}",
                corner(&sharp, c)
            );
        }
        for c in [6, 7] {
            assert!(corner(&sharp, c)[1] < -0.9999, "{:?}", corner(&sharp, c));
        }
        let mut smooth = m.clone();
        assert_eq!(crease_normals(&mut smooth, 120.0), 0);
        assert_eq!(corner(&smooth, 0), corner(&smooth, 6));
    }
}
