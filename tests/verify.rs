//! `verify` against its oracle: the fast cut check (`builder::verify`) must give the same report,
//! violation for violation, as the straightforward one it replaced (`verify_reference`), on good
//! meshes and on deliberately broken DAGs; and it must fail every broken DAG: a triangle removed
//! from a simplified cluster (cracks), a triangle duplicated (overlap), a zero-area triangle, a
//! border crack, and a group's error lowered so that the cut is not monotonic. (Level 0 is the
//! input to `verify`: edits there change the input, not the DAG's soundness; one test shows it.)

mod common;

use common::path_crossings;
use common::shapes::{append, grid, mesh_from, sphere};

use vgeo::builder::{self, BuildOptions, BuiltMesh, VerifyOptions, VerifyReport};

fn build(name: &str, m: (Vec<[f32; 3]>, Vec<u32>)) -> BuiltMesh {
    builder::build(&mesh_from(name, m.0, m.1), &BuildOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn views(n: usize) -> VerifyOptions {
    VerifyOptions {
        views: n,
        ..Default::default()
    }
}

/// Runs both verifiers; asserts identical reports (every count and every message) and returns it.
fn both(name: &str, m: &BuiltMesh, opts: &VerifyOptions) -> VerifyReport {
    let fast = builder::verify(m, opts);
    let reference = builder::verify::verify_reference(m, opts);
    assert_eq!(
        fast, reference,
        "{name}: the fast verify differs from the reference\nfast: {fast}\nreference: {reference}"
    );
    assert_eq!(fast.views_tested, opts.views, "{name}");
    fast
}

/// Cluster `ci`'s triangles as local indices.
fn local_triangles(m: &BuiltMesh, ci: usize) -> Vec<[u8; 3]> {
    m.cluster_local_triangles(&m.clusters[ci])
        .into_iter()
        .map(|t| t.map(|l| l as u8))
        .collect()
}

/// Replaces cluster `ci`'s triangles (local indices into its vertices), packed at the end of the
/// triangle buffer.
fn set_local_triangles(m: &mut BuiltMesh, ci: usize, tris: &[[u8; 3]]) {
    assert!(!tris.is_empty() && tris.len() <= 128);
    let c = m.clusters[ci];
    let local: Vec<u8> = tris.iter().flatten().copied().collect();
    let mut packed = Vec::new();
    builder::pack_indices(&local, c.vertex_count(), &mut packed);
    while !m.triangles.len().is_multiple_of(4) {
        m.triangles.push(0);
    }
    let at = m.triangles.len();
    m.triangles.extend_from_slice(&packed);
    let c = &mut m.clusters[ci];
    c.triangle_offset = at as u32;
    c.counts = c.vertex_count() | (tris.len() as u32) << 8 | c.flags() << 16;
    // The size code of the new triangles (what the builder would store).
    let code = builder::size::cluster_size_code(
        m.cluster_triangles(ci)
            .iter()
            .map(|t| t.map(|v| m.position(v))),
        m.clusters[ci].bounds_min,
        m.clusters[ci].bounds_max,
    );
    m.clusters[ci].counts |= code << 24;
    // Lay the pages out again, so that the new triangles lie in the cluster's page.
    let level = m.fallback_level(BuildOptions::default().fallback_triangles);
    builder::page::paginate(m, builder::page::PAGE_BYTES as usize, level);
}

/// The numbers before " unmatched and " and " over-used edges" summed over the report's lines.
fn crack_and_overlap_edges(r: &VerifyReport) -> (usize, usize) {
    let mut out = (0, 0);
    for v in &r.violations {
        if let Some((head, tail)) = v.split_once(" unmatched and ") {
            let n = |s: &str| s.parse::<usize>().expect("a count");
            out.0 += n(head.rsplit(' ').next().expect("count"));
            out.1 += n(tail.split(' ').next().expect("count"));
        }
    }
    out
}

fn has(r: &VerifyReport, what: &str) -> bool {
    r.violations.iter().any(|v| v.contains(what))
}

/// A cluster of the sample's sphere part (every vertex on the sphere: away from the grid and its
/// border), at `level`, with `min_tris` triangles at least.
fn interior_cluster(m: &BuiltMesh, level: u32, min_tris: u32) -> usize {
    let positions = m.positions();
    let on_sphere = |v: u32| {
        let p = positions[v as usize];
        let d2 = (p[0] - 5.0).powi(2) + (p[1] - 1.0).powi(2) + p[2].powi(2);
        d2 < 1.0
    };
    (0..m.clusters.len())
        .find(|&c| {
            let cl = &m.clusters[c];
            cl.level == level
                && cl.triangle_count() >= min_tris
                && c != m.root as usize
                && m.cluster_triangles(c)
                    .iter()
                    .flatten()
                    .all(|&v| on_sphere(v))
        })
        .expect("a sphere cluster at that level")
}

fn sample() -> BuiltMesh {
    let mut m = (Vec::new(), Vec::new());
    append(&mut m, grid(40, 30, [0.0; 3], 0.1));
    append(&mut m, sphere(48, 32, [5.0, 1.0, 0.0], 0.7));
    build("sample", m)
}

/// Good meshes of several kinds (closed, open borders and holes, islands, non-manifold fins and
/// duplicate faces, a one-quad strip whose every point is on the border): both verifiers pass
/// and agree on every count.
#[test]
fn fast_verify_matches_reference_on_good_meshes() {
    let mut holes = grid(50, 50, [0.0; 3], 1.0);
    let p = holes.0.clone();
    let tris: Vec<[u32; 3]> = holes
        .1
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    holes.1 = tris
        .into_iter()
        .filter(|t| {
            let c = [0, 1].map(|k| t.iter().map(|&v| p[v as usize][k]).sum::<f32>() / 3.0);
            let hole = |x: f32, y: f32, r: f32| (c[0] - x).abs() < r && (c[1] - y).abs() < r;
            !(hole(10.0, 10.0, 3.0) || hole(30.0, 25.0, 5.0))
        })
        .flatten()
        .collect();
    let mut islands = (Vec::new(), Vec::new());
    for k in 0..120u32 {
        let c = [(k % 12) as f32 * 3.0, (k / 12) as f32 * 3.0, (k % 7) as f32];
        append(&mut islands, sphere(6, 4, c, 1.0));
    }
    let (mut fin_p, mut fin_i) = grid(30, 20, [0.0; 3], 1.0);
    for k in 0..20u32 {
        let a = k * 31 + 5;
        let top = fin_p.len() as u32;
        fin_p.push([5.0, k as f32 + 0.5, 2.0]);
        fin_i.extend_from_slice(&[a, a + 31, top]);
    }
    let dup: Vec<u32> = fin_i[300..600].to_vec();
    fin_i.extend(dup);
    let meshes = [
        ("sample", sample()),
        ("holes", build("holes", holes)),
        ("islands", build("islands", islands)),
        ("nonmanifold", build("nonmanifold", (fin_p, fin_i))),
        ("strip", build("strip", grid(1, 300, [0.0; 3], 0.1))),
    ];
    for (name, m) in &meshes {
        let r = both(name, m, &views(48));
        assert!(r.ok(), "{name}: {r}");
        assert!(r.cut_triangles_max > r.cut_triangles_min, "{name}: {r}");
    }
    // The open-border rules were exercised.
    let holes = both("holes", &meshes[1].1, &views(48));
    assert!(holes.border_loops >= 3, "{holes}");
    assert!(holes.border_edges_accepted > 0, "{holes}");
}

/// Small real meshes with what scans and CAD exports bring: many holes (elephant-with-holes), and
/// islands, duplicate faces, zero-area triangles and non-manifold edges (Spider): the same report
/// from both, and OK.
#[test]
fn fast_verify_matches_reference_on_real_meshes() {
    for file in ["hard/elephant-with-holes.off", "hard/Spider_binary.stl"] {
        let path = common::shared_assets().join(file);
        let mesh = vgeo::mesh::merge(
            vgeo::build_files::load_input(&path, &Default::default()).expect(file),
        );
        let m = builder::build(&mesh, &BuildOptions::default()).expect(file);
        let r = both(file, &m, &views(64));
        assert!(r.ok(), "{file}: {r}");
        // Both have open-border loops, so the border-chain check ran on them.
        assert!(r.border_loops > 0, "{file}: {r}");
    }
}

/// Index of a triangle of `tris` whose three edges are all matched inside the cluster (each used
/// the other way by another of its triangles): breaking it touches no cluster border.
fn inner_triangle(tris: &[[u8; 3]]) -> usize {
    let matched = |t: &[u8; 3], e: usize| {
        tris.iter()
            .any(|u| (0..3).any(|k| u[k] == t[(e + 1) % 3] && u[(k + 1) % 3] == t[e]))
    };
    tris.iter()
        .position(|t| (0..3).all(|e| matched(t, e)))
        .expect("an inner triangle")
}

/// Level 0 is the input as far as `verify` knows (it has no other copy of it): a triangle
/// removed there is an input hole, which every cut must show, so the DAG is still sound. The
/// report is OK and counts one more simple border loop (the hole's three edges).
#[test]
fn verify_takes_level_0_as_the_input() {
    let good = sample();
    let before = both("sample", &good, &views(16));
    assert!(before.ok(), "{before}");
    let mut m = good.clone();
    let ci = interior_cluster(&m, 0, 16);
    let mut tris = local_triangles(&m, ci);
    tris.remove(inner_triangle(&tris));
    set_local_triangles(&mut m, ci, &tris);
    let r = both("level-0 triangle removed", &m, &views(16));
    assert!(r.ok(), "{r}");
    assert_eq!(r.border_loops, before.border_loops + 1, "{r}");
}

/// One triangle removed from a simplified cluster (levels 1 to 3): its three edges are unmatched
/// (cracks) in every cut that draws the cluster; nothing is over-used.
#[test]
fn verify_fails_removed_triangle() {
    let good = sample();
    for level in 1..=3 {
        let mut m = good.clone();
        let ci = interior_cluster(&m, level, 16);
        let mut tris = local_triangles(&m, ci);
        tris.remove(inner_triangle(&tris));
        set_local_triangles(&mut m, ci, &tris);
        let r = both(&format!("level-{level} triangle removed"), &m, &views(64));
        assert!(!r.ok(), "level {level}: not found: {r}");
        let (cracks, overlaps) = crack_and_overlap_edges(&r);
        assert!(cracks > 0 && overlaps == 0, "level {level}: {r}");
        assert!(
            has(&r, "3 unmatched and 0 over-used edges"),
            "level {level}: {r}"
        );
    }
}

/// A triangle of a simplified cluster duplicated: its three edges are used twice in one direction
/// (overlap) in every cut that draws the cluster; nothing is unmatched.
#[test]
fn verify_fails_duplicated_triangle() {
    let mut m = sample();
    let ci = (0..m.clusters.len())
        .find(|&c| m.clusters[c].level == 1 && m.clusters[c].triangle_count() < 128)
        .expect("a level-1 cluster with room");
    let mut tris = local_triangles(&m, ci);
    tris.push(tris[inner_triangle(&tris)]);
    set_local_triangles(&mut m, ci, &tris);
    let r = both("duplicated triangle", &m, &views(64));
    assert!(!r.ok(), "{r}");
    let (cracks, overlaps) = crack_and_overlap_edges(&r);
    assert!(overlaps > 0 && cracks == 0, "{r}");
    assert!(has(&r, "0 unmatched and 3 over-used edges"), "{r}");
}

/// A triangle [a, b, c] of a simplified cluster replaced by the zero-area [a, a, b]: an edge from
/// a point to itself (which both verifiers count the same way), a -> b used twice the other way
/// (overlap), and b -> c, c -> a left unmatched (cracks).
#[test]
fn verify_fails_zero_area_triangle() {
    let mut m = sample();
    let ci = interior_cluster(&m, 1, 16);
    let mut tris = local_triangles(&m, ci);
    let i = inner_triangle(&tris);
    tris[i] = [tris[i][0], tris[i][0], tris[i][1]];
    set_local_triangles(&mut m, ci, &tris);
    let r = both("zero-area triangle", &m, &views(64));
    assert!(!r.ok(), "{r}");
    assert!(has(&r, "2 unmatched and 1 over-used edges"), "{r}");
}

/// A crack on an open border (a root triangle of a one-quad strip removed, every point on the
/// border): found by the border-chain check, the same in both.
#[test]
fn verify_fails_border_crack() {
    let mut m = build("strip", grid(1, 300, [0.0; 3], 0.1));
    let root = m.root as usize;
    let tris = local_triangles(&m, root);
    let key = |t: &[u8; 3], e: usize| (t[e], t[(e + 1) % 3]);
    let border_edges = |t: &[u8; 3]| {
        (0..3)
            .filter(|&e| {
                let (a, b) = key(t, e);
                !tris.iter().any(|u| (0..3).any(|k| key(u, k) == (b, a)))
            })
            .count()
    };
    let victim = tris
        .iter()
        .position(|t| border_edges(t) == 1)
        .expect("a root triangle with one border edge");
    let rest: Vec<[u8; 3]> = tris
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != victim)
        .map(|(_, t)| *t)
        .collect();
    set_local_triangles(&mut m, root, &rest);
    let r = both("strip with a border crack", &m, &views(64));
    assert!(!r.ok(), "{r}");
    assert!(has(&r, "border chains broken"), "{r}");
}

/// A group's error lowered (its members' parent error and its simplified clusters' self error
/// with it, so each pair still matches its group): the cut is not monotonic. The DAG check
/// rejects the order, and the views see level-0 clusters covered twice or not at all.
#[test]
fn verify_fails_non_monotonic_error() {
    let good = sample();
    let ci = interior_cluster(&good, 1, 1);
    let g = good.clusters[ci].group as usize;
    let mut m = good.clone();
    let lowered = m.groups[g].error * 1e-3;
    m.groups[g].error = lowered;
    for c in &mut m.clusters {
        if c.group as usize == g {
            c.parent_error = lowered;
        }
        if c.creator as usize == g {
            c.self_error = lowered;
        }
    }
    let r = both("lowered group error", &m, &views(64));
    assert!(!r.ok(), "{r}");
    assert!(has(&r, "> parent error"), "{r}");
    assert!(has(&r, "not covered exactly once"), "{r}");
}

/// Under a closed page residency (`page::close_residency`) the cut draws only resident clusters
/// and crosses every leaf-to-root path once; the BVH walk finds the same cut. A residency that is
/// not closed (a group resident without the pages its products need) breaks the cut: the check
/// can fail. `verify` tests such cuts in every fourth view.
#[test]
fn cuts_under_closed_residency_are_sound_and_draw_only_resident_pages() {
    use builder::cut::{cut_brute, cut_bvh, proj_scale};
    use builder::page::{close_residency, group_needs, paginate};
    let mut m = sample();
    // Small pages, so that the sample has many, and resident from a level of at most 1000
    // triangles (2000 before session 37: at the step ratio 0.35 that is level 1, and no group
    // needed a page but its own beyond the resident ones).
    let level = m.fallback_level(1000);
    paginate(&mut m, 4096, level);
    assert!(m.pages.len() >= 12, "{} pages", m.pages.len());
    let needs = group_needs(&m);
    let scale = proj_scale(1080.0, 60f32.to_radians());
    let cams = [
        glam::Vec3::new(2.0, 1.0, 3.0),
        glam::Vec3::new(5.0, 1.0, 2.5),
        glam::Vec3::new(-20.0, 5.0, 10.0),
    ];
    let mut partial_cuts = 0;
    for seed in 0..12u32 {
        let mut res: Vec<bool> = (0..m.pages.len())
            .map(|p| (p as u32 * 7 + seed * 13) % 5 < seed % 5)
            .collect();
        close_residency(&m, &needs, &mut res);
        for cam in cams {
            for tau in [0.0, 0.5, 2.0, 8.0] {
                let cut = cut_brute(&m, cam, scale, tau, Some(&res));
                assert_eq!(cut_bvh(&m, cam, scale, tau, Some(&res)), Some(cut.clone()));
                for &c in &cut {
                    assert!(
                        res[m.clusters[c as usize].page as usize],
                        "cluster {c} not resident"
                    );
                }
                let up = path_crossings(&m, &cut);
                for (ci, c) in m.clusters.iter().enumerate() {
                    if c.level == 0 {
                        assert_eq!(up[ci], (1, 1), "seed {seed}, tau {tau}: cluster {ci}");
                    }
                }
                if cut != cut_brute(&m, cam, scale, tau, None) {
                    partial_cuts += 1;
                }
            }
        }
    }
    assert!(
        partial_cuts > 20,
        "residency changed only {partial_cuts} cuts"
    );
    // Not closed: every page resident but one that a resident group needs.
    let (g, p) = needs
        .iter()
        .enumerate()
        .find_map(|(g, n)| {
            let own = m.groups[g].page_first..m.groups[g].page_first + m.groups[g].page_count;
            n.iter()
                .find(|&&p| !own.contains(&p) && p >= m.resident_pages)
                .map(|&p| (g, p))
        })
        .expect("a group needing another page");
    let mut res = vec![true; m.pages.len()];
    res[p as usize] = false;
    let broken = (0..64).any(|k| {
        let cam = m.groups[g].lod_sphere;
        let cam = glam::Vec3::new(cam[0], cam[1], cam[2] + 0.05 * k as f32);
        [0.0, 0.25, 1.0, 4.0].iter().any(|&tau| {
            let cut = cut_brute(&m, cam, scale, tau, Some(&res));
            let up = path_crossings(&m, &cut);
            m.clusters
                .iter()
                .enumerate()
                .any(|(ci, c)| c.level == 0 && up[ci] != (1, 1))
        })
    });
    assert!(broken, "an open residency set must break some cut");
}
