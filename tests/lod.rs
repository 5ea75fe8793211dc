//! The discrete-LOD baseline (`lod`): its levels (counts, errors), per-instance selection, and its
//! images against `brute` on the GPU (lavapipe in CI) with the validation layer on.

mod common;

use common::{assert_no_validation_errors, gpu, shared_assets};
use glam::{DMat4, DVec3, Vec3};
use vgeo::baseline::brute::Brute;
use vgeo::baseline::lod::{
    LOD_COUNT, LOD_FRACTIONS, LOD_MIN_TRIANGLES, Lod, LodChain, LodOptions, select_lod,
};
use vgeo::camera::Camera;
use vgeo::material::ShadeMode;
use vgeo::mesh::Mesh;
use vgeo::render::{Frame, Light, Placement};
use vgeo::scene::load::LoadedScene;

fn load(rel: &str) -> Mesh {
    let path = shared_assets().join(rel);
    let scene = LoadedScene::load(&path).unwrap_or_else(|e| panic!("{}: {e:#}", path.display()));
    scene.mesh(0).clone()
}

fn bunny() -> Mesh {
    load("scanned/bunny.ply")
}

/// A mesh from triangles with face normals (welded nothing: tests only need positions).
fn mesh_from(positions: Vec<[f32; 3]>, indices: Vec<u32>) -> Mesh {
    let n = positions.len();
    Mesh {
        name: "test".into(),
        normals: vec![[0.0, 0.0, 1.0]; n],
        uvs: vec![[0.0; 2]; n],
        material_ids: vec![0; indices.len() / 3],
        materials: vec![Default::default()],
        positions,
        indices,
        has_normals: false,
        has_uvs: false,
    }
}

fn placement_at(p: DVec3) -> Placement {
    Placement {
        mesh: 0,
        transform: DMat4::from_translation(p),
        color: [0.8, 0.7, 0.6],
    }
}

/// Camera at the origin looking down -z.
fn camera() -> Camera {
    Camera::look_at(
        DVec3::ZERO,
        DVec3::new(0.0, 0.0, -1.0),
        Vec3::Y,
        45f32.to_radians(),
        0.01,
    )
}

fn check_chain(name: &str, chain: &LodChain, full: u32) {
    let counts = chain.triangle_counts();
    assert_eq!(counts[0], full, "{name}: level 0 is the full mesh");
    for k in 1..LOD_COUNT {
        if counts[k - 1] as usize <= LOD_MIN_TRIANGLES {
            // The chain stops halving at a small level: the rest share it.
            assert_eq!(
                counts[k],
                counts[k - 1],
                "{name}: level {k} after the last; {counts:?}"
            );
            assert_eq!(chain.ranges[k], chain.ranges[k - 1]);
            continue;
        }
        let target = full as f32 * LOD_FRACTIONS[k];
        let ratio = counts[k] as f32 / target;
        assert!(
            (0.9..=1.02).contains(&ratio),
            "{name}: level {k} has {} triangles, target {target:.0} (ratio {ratio:.3}); counts {counts:?}",
            counts[k]
        );
    }
    assert_eq!(chain.errors[0], 0.0, "{name}: level 0 is exact");
    for k in 1..LOD_COUNT {
        assert!(
            chain.errors[k] >= chain.errors[k - 1] && chain.errors[k].is_finite(),
            "{name}: errors must not decrease: {:?}",
            chain.errors
        );
    }
    assert!(
        chain.errors[LOD_COUNT - 1] > 0.0,
        "{name}: the coarsest level must report an error: {:?}",
        chain.errors
    );
    // The coverage parts: 0 at level 0, non-decreasing, at most the errors.
    assert_eq!(chain.coverages[0], 0.0);
    for k in 1..LOD_COUNT {
        assert!(
            chain.coverages[k] >= chain.coverages[k - 1] && chain.coverages[k] <= chain.errors[k],
            "{name}: coverages {:?}, errors {:?}",
            chain.coverages,
            chain.errors
        );
    }
    // Ranges lie inside the index buffer and hold whole triangles.
    for &(first, count) in &chain.ranges {
        assert!(first as usize + count as usize <= chain.indices.len());
        assert_eq!(count % 3, 0);
    }
    eprintln!("{name}: counts {counts:?}, errors {:?}", chain.errors);
}

#[test]
fn level_counts_follow_fractions_and_errors_grow() {
    let b = bunny();
    check_chain("bunny", &LodChain::build(&b), b.triangle_count() as u32);
    // With UV seams and normals (split vertices).
    let s = load("scanned/spot.obj");
    check_chain("spot", &LodChain::build(&s), s.triangle_count() as u32);
    // Deterministic.
    assert_eq!(LodChain::build(&b), LodChain::build(&b));
}

#[test]
fn tiny_meshes_keep_equal_levels() {
    // One triangle cannot shrink: every level is that triangle, sharing one range, error 0.
    let tri = mesh_from(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        vec![0, 1, 2],
    );
    let c = LodChain::build(&tri);
    assert_eq!(c.triangle_counts(), [1; LOD_COUNT]);
    assert_eq!(c.ranges, [(0, 3); LOD_COUNT], "no duplicated indices");
    assert_eq!(c.errors, [0.0; LOD_COUNT]);
    assert_eq!(c.indices, vec![0, 1, 2]);

    // A closed tetrahedron (4 triangles): levels never grow, errors never shrink.
    let tet = mesh_from(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        vec![0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3],
    );
    let c = LodChain::build(&tet);
    let counts = c.triangle_counts();
    eprintln!("tetrahedron: counts {counts:?}, errors {:?}", c.errors);
    assert_eq!(counts[0], 4);
    // meshoptimizer would collapse it to nothing at 1 triangle: no level is ever empty.
    assert!(counts.iter().all(|&n| n > 0), "an empty level: {counts:?}");
    for k in 1..LOD_COUNT {
        assert!(counts[k] <= counts[k - 1], "counts grow: {counts:?}");
        assert!(
            c.errors[k] >= c.errors[k - 1],
            "errors shrink: {:?}",
            c.errors
        );
        if counts[k] == counts[k - 1] {
            assert_eq!(
                c.ranges[k],
                c.ranges[k - 1],
                "an equal level shares its range"
            );
        }
    }

    // An empty mesh has empty levels.
    let empty = mesh_from(Vec::new(), Vec::new());
    let c = LodChain::build(&empty);
    assert_eq!(c.triangle_counts(), [0; LOD_COUNT]);
    assert_eq!(c.errors, [0.0; LOD_COUNT]);
}

/// `select_lod` of an instance of `chain` placed by `t`.
fn chain_level(chain: &LodChain, t: &DMat4, eye: DVec3, ps: f32, tau: f32) -> u8 {
    select_lod(
        &chain.errors,
        &chain.coverages,
        &chain.sphere,
        t,
        eye,
        ps,
        tau,
    )
}

#[test]
fn selection_follows_distance() {
    let chain = LodChain::build(&bunny());
    let cam = camera();
    let ps = vgeo::builder::cut::proj_scale(720.0, cam.fov_y);
    let pick = |d: f64, tau: f32, t: DMat4| {
        let t = DMat4::from_translation(DVec3::new(0.0, 0.0, -d)) * t;
        chain_level(&chain, &t, cam.position, ps, tau)
    };
    let mut levels = Vec::new();
    let mut d = 0.05;
    while d < 1000.0 {
        levels.push((d, pick(d, 1.0, DMat4::IDENTITY)));
        d *= 1.25;
    }
    assert_eq!(
        levels[0].1, 0,
        "up close (camera inside the sphere): level 0"
    );
    assert_eq!(
        levels.last().unwrap().1,
        (LOD_COUNT - 1) as u8,
        "far away: the coarsest level"
    );
    for w in levels.windows(2) {
        assert!(
            w[1].1 >= w[0].1,
            "not monotonic in distance: {:?} then {:?}",
            w[0],
            w[1]
        );
    }
    // Every level is used somewhere along the way (but one with the same error as the next,
    // coarser one: the coarser is always as good).
    for k in 0..LOD_COUNT as u8 {
        if (k as usize) < LOD_COUNT - 1 && chain.errors[k as usize] >= chain.errors[k as usize + 1]
        {
            continue;
        }
        assert!(
            levels.iter().any(|l| l.1 == k),
            "level {k} never picked: {levels:?}"
        );
    }
    // The threshold decides: exactly at the switch distance of level 3 and 1 px.
    let (r, e) = (chain.sphere[3], chain.errors[3]);
    let center = Vec3::from_slice(&chain.sphere[..3]);
    let px_at = |d: f64| {
        vgeo::builder::cut::lod_error_px(
            e,
            center + Vec3::new(0.0, 0.0, -d as f32),
            r,
            Vec3::ZERO,
            ps,
        )
    };
    for &(d, lvl) in &levels {
        assert_eq!(
            lvl >= 3,
            px_at(d) <= 1.0,
            "level 3 or coarser iff level 3's error is within 1 px (d {d}, {} px)",
            px_at(d)
        );
    }
    // Zero threshold: full detail everywhere.
    assert!(
        levels
            .iter()
            .all(|&(d, _)| pick(d, 0.0, DMat4::IDENTITY) == 0)
    );
    // A larger threshold never picks a finer level; scaling the instance up picks finer ones.
    for &(d, lvl) in &levels {
        assert!(pick(d, 4.0, DMat4::IDENTITY) >= lvl);
        assert!(pick(d, 1.0, DMat4::from_scale(DVec3::splat(3.0))) <= lvl);
    }
}

/// "1 px" means what vgeo's culls mean: the cut's `lod_error_px` of the level's error and the
/// mesh's sphere, both scaled by the instance's largest axis scale (the `max_scale` vgeo's
/// instances carry), the sphere moved by the transform, the error weighted for a small instance
/// (`small_instance_weight`, its coverage part whole) as vgeo weighs it; for scaled, rotated,
/// far-off instances.
#[test]
fn selection_is_the_cut_formula_with_the_instance_scale() {
    use vgeo::builder::cut::{lod_error_px, proj_scale, small_instance_weight};
    let chain = LodChain::build(&bunny());
    let cam = Camera::look_at(
        DVec3::new(1.0e5, 20.0, -3.0),
        DVec3::new(1.0e5, 20.0, -10.0),
        Vec3::Y,
        50f32.to_radians(),
        0.01,
    );
    let ps = proj_scale(1080.0, cam.fov_y);
    let centre = DVec3::from(Vec3::from_slice(&chain.sphere[..3]));
    let mut picked = [0u32; LOD_COUNT];
    for i in 0..400 {
        let f = i as f64;
        let scale = DVec3::new(
            0.5 + (f * 0.37).sin().abs() * 3.0,
            1.0 + (f * 0.11).cos(),
            0.7,
        );
        let rot = glam::DQuat::from_euler(glam::EulerRot::YXZ, f * 0.3, f * 0.17, f * 0.05);
        let pos = cam.position + DVec3::new((f * 0.7).sin() * 2.0, 0.3, -0.2 - (f * 0.03).exp2());
        let t = DMat4::from_scale_rotation_translation(scale, rot, pos);
        let p = Placement {
            mesh: 0,
            transform: t,
            color: [1.0; 3],
        };
        // vgeo's instance record carries the same scale.
        let s = vgeo::render::max_axis_scale(&t);
        assert_eq!(vgeo::scene_gpu::instance_gpu(&p).max_scale, s);
        assert!((s as f64 - scale.max_element()).abs() < 1e-5 * scale.max_element());
        let rel = (t.transform_point3(centre) - cam.position).as_vec3();
        // A small instance counts a share of its errors (its sphere's projected radius), their
        // coverage part whole.
        let radius = chain.sphere[3] * s;
        let w = small_instance_weight(lod_error_px(radius, rel, radius, Vec3::ZERO, ps));
        for tau in [0.5f32, 1.0, 4.0] {
            let expect = (1..LOD_COUNT)
                .rev()
                .find(|&k| {
                    lod_error_px(
                        (chain.errors[k] * w).max(chain.coverages[k]) * s,
                        rel,
                        chain.sphere[3] * s,
                        Vec3::ZERO,
                        ps,
                    ) <= tau
                })
                .unwrap_or(0) as u8;
            let got = chain_level(&chain, &t, cam.position, ps, tau);
            assert_eq!(got, expect, "instance {i}, {tau} px");
            picked[got as usize] += 1;
        }
    }
    // The instances span the levels, so the comparison covers each switch.
    assert!(
        picked
            .iter()
            .enumerate()
            .all(|(k, &n)| n > 0 || k + 1 < LOD_COUNT && chain.errors[k] >= chain.errors[k + 1]),
        "{picked:?}, errors {:?}",
        chain.errors
    );
}

/// Share of pixels where both frames agree on coverage, and share of those covered by both whose
/// depth agrees within a relative `tol`.
fn agreement(a: &Frame, b: &Frame, tol: f32) -> (f64, f64) {
    let n = a.depth.len();
    let (mut same, mut both, mut depth_ok) = (0usize, 0usize, 0usize);
    for (&x, &y) in a.depth.iter().zip(&b.depth) {
        if (x > 0.0) == (y > 0.0) {
            same += 1;
        }
        if x > 0.0 && y > 0.0 {
            both += 1;
            if (x - y).abs() <= tol * x.max(y) {
                depth_ok += 1;
            }
        }
    }
    (same as f64 / n as f64, depth_ok as f64 / both.max(1) as f64)
}

/// A row of bunnies at growing distances, all in view: the first one around the camera (inside its
/// bounding sphere, so level 0 at any threshold), the others from 0.15 to 2.4 units away.
fn bunny_row(chain: &LodChain) -> Vec<Placement> {
    let c = DVec3::new(
        chain.sphere[0] as f64,
        chain.sphere[1] as f64,
        chain.sphere[2] as f64,
    );
    let r = chain.sphere[3] as f64;
    let mut centers = vec![DVec3::new(0.7 * r, 0.0, -0.5 * r)];
    centers.extend((0..5).map(|i| {
        let d = 0.15 * 2f64.powi(i);
        DVec3::new(-0.3 * d, -0.05 * d, -d)
    }));
    centers.into_iter().map(|p| placement_at(p - c)).collect()
}

#[test]
fn zero_threshold_matches_brute_exactly() {
    let ctx = gpu();
    let meshes = vec![bunny()];
    let lod = Lod::new(&ctx, &meshes, &LodOptions::default()).expect("lod renderer");
    let brute = Brute::new(&ctx, &meshes).expect("brute renderer");
    let placements = bunny_row(&LodChain::build(&meshes[0]));
    let cam = camera();
    let light = Light::default();
    let (w, h) = (96, 64);
    // The scene is meaningful: at 1 px the levels differ between instances.
    let sel = lod.selection(&placements, &cam, h, 1.0).expect("selection");
    assert!(
        sel.contains(&0) && sel.iter().any(|&l| l > 0),
        "the row should mix levels at 1 px: {sel:?}"
    );
    let sel0 = lod.selection(&placements, &cam, h, 0.0).expect("selection");
    assert!(sel0.iter().all(|&l| l == 0), "{sel0:?}");

    let b = brute
        .render(&placements, &cam, &light, w, h)
        .expect("brute");
    let l0 = lod
        .render(&placements, &cam, &light, w, h, 0.0)
        .expect("lod");
    assert!(b.covered() > 200, "the row is visible: {}", b.covered());
    assert_eq!(l0.triangles, b.triangles);
    assert!(l0.color == b.color, "colour differs from brute at 0 px");
    assert!(l0.depth == b.depth, "depth differs from brute at 0 px");

    // The second frame has the first one's HZB: an instance it hides is not drawn.
    let (l1, stats) = lod
        .render_with_stats(&placements, &cam, &light, (w, h), 1.0, ShadeMode::Lit)
        .expect("lod");
    let gpu_sel: Vec<u8> = stats.levels.iter().map(|l| l.expect("in view")).collect();
    assert_eq!(gpu_sel, sel, "the GPU picks the CPU's levels");
    let counts = lod.lod_triangle_counts(0);
    let expect: u64 = (sel.iter().zip(&stats.occluded_instances))
        .filter(|(_, o)| !**o)
        .map(|(&l, _)| counts[l as usize] as u64)
        .sum();
    assert_eq!(l1.triangles, expect, "triangles drawn = selected levels");
    assert!(l1.triangles < b.triangles);
    assert_no_validation_errors(&ctx);
}

#[test]
fn far_bunny_stays_close_to_brute() {
    let ctx = gpu();
    let path = shared_assets().join("scanned/bunny.ply");
    let scene = LoadedScene::load(&path).expect("bunny loads");
    let (w, h) = (128, 128);
    let cam = scene.camera(w, h);
    let lod = Lod::new(&ctx, &scene.meshes(), &LodOptions::default()).expect("lod renderer");
    let brute = Brute::new(&ctx, &scene.meshes()).expect("brute renderer");
    let sel = lod
        .selection(&scene.placements, &cam, h, 1.0)
        .expect("selection");
    let counts = lod.lod_triangle_counts(0);
    let errors = lod.lod_errors(0);
    assert_eq!(
        counts,
        vgeo::baseline::lod::LodChain::build(scene.mesh(0)).triangle_counts()
    );
    assert!(
        sel[0] >= 2,
        "auto-framed bunny at {w}x{h} should get a coarse level at 1 px: level {}, errors {errors:?}",
        sel[0]
    );
    let b = brute
        .render(&scene.placements, &cam, &scene.light, w, h)
        .expect("brute");
    let l = lod
        .render(&scene.placements, &cam, &scene.light, w, h, 1.0)
        .expect("lod");
    assert_eq!(l.triangles, counts[sel[0] as usize] as u64);
    let (cover, depth) = agreement(&b, &l, 1e-3);
    let msg = format!(
        "level {} ({} of {} triangles): coverage agreement {cover:.4}, depth agreement {depth:.4} \
         (brute covers {} px, lod {} px)",
        sel[0],
        l.triangles,
        b.triangles,
        b.covered(),
        l.covered()
    );
    eprintln!("{msg}");
    assert!(b.covered() > 2000, "{msg}");
    // Measured on lavapipe: coverage 0.9991, depth 0.798 (level 3, 8,680 triangles; 0.951 with
    // position-only simplification, 0.863 with normal weight 0.5: weighing normals moves some
    // vertices more, within the same projected error bound, since the error is the combined one).
    assert!(cover >= 0.995, "{msg}");
    assert!(depth >= 0.77, "{msg}");
    assert_no_validation_errors(&ctx);
}

#[test]
fn bias_and_bad_input() {
    let ctx = gpu();
    let meshes = vec![bunny()];
    let placements = bunny_row(&LodChain::build(&meshes[0]));
    let cam = camera();
    let fine = Lod::new(&ctx, &meshes, &LodOptions::default()).expect("lod");
    let opts = LodOptions {
        lod_bias: 8.0,
        ..Default::default()
    };
    let coarse = Lod::new(&ctx, &meshes, &opts).expect("lod");
    // A high image (2000 px) so the far bunnies are not all at the coarsest level already.
    let a = fine
        .selection(&placements, &cam, 2000, 1.0)
        .expect("selection");
    let b = coarse
        .selection(&placements, &cam, 2000, 1.0)
        .expect("selection");
    eprintln!("selection at 2000 px high, bias 1: {a:?}, bias 8: {b:?}");
    assert!(a.iter().zip(&b).all(|(x, y)| y >= x), "{a:?} vs {b:?}");
    assert!(
        b.iter().sum::<u8>() > a.iter().sum::<u8>(),
        "{a:?} vs {b:?}"
    );
    // Same as threshold 8 px with bias 1.
    assert_eq!(
        b,
        fine.selection(&placements, &cam, 2000, 8.0)
            .expect("selection")
    );

    let mut bad = placements.clone();
    bad[2].mesh = 7;
    let err = fine
        .render(&bad, &cam, &Light::default(), 32, 32, 1.0)
        .expect_err("a placement of a missing mesh is an error");
    assert!(err.to_string().contains("mesh 7"), "{err}");
    assert!(fine.selection(&bad, &cam, 32, 1.0).is_err());
    // No placements: a cleared frame.
    let f = fine
        .render(&[], &cam, &Light::default(), 32, 32, 1.0)
        .expect("empty frame");
    assert_eq!((f.triangles, f.covered()), (0, 0));
    assert_no_validation_errors(&ctx);
}

#[test]
fn frustum_culling_skips_only_invisible_instances() {
    let ctx = gpu();
    let meshes = vec![bunny()];
    let chain = LodChain::build(&meshes[0]);
    let c = DVec3::from(Vec3::from_slice(&chain.sphere[..3]));
    let cam = camera();
    let light = Light::default();
    let (w, h) = (64, 48);
    // In view, behind the camera, far to the side, and one straddling the left edge.
    let at = |p: DVec3| placement_at(p - c);
    let placements = vec![
        at(DVec3::new(0.0, 0.0, -0.5)),
        at(DVec3::new(0.0, 0.0, 0.5)),
        at(DVec3::new(5.0, 0.0, -0.5)),
        at(DVec3::new(0.0, -5.0, -0.5)),
        at(DVec3::new(-0.5 * 0.414 * 64.0 / 48.0 - 0.02, 0.0, -0.5)),
    ];
    let culling = Lod::new(&ctx, &meshes, &LodOptions::default()).expect("lod");
    let all = Lod::new(
        &ctx,
        &meshes,
        &LodOptions {
            frustum_cull: false,
            ..Default::default()
        },
    )
    .expect("lod");
    let a = culling
        .render(&placements, &cam, &light, w, h, 0.0)
        .expect("render");
    let b = all
        .render(&placements, &cam, &light, w, h, 0.0)
        .expect("render");
    let full = meshes[0].triangle_count() as u64;
    assert_eq!(
        b.triangles,
        5 * full,
        "without culling every instance is drawn"
    );
    assert_eq!(
        a.triangles,
        2 * full,
        "the centred and the straddling instances remain"
    );
    assert!(a.covered() > 100, "something is visible: {}", a.covered());
    assert!(
        a.color == b.color && a.depth == b.depth,
        "culling changed the image"
    );
    assert_no_validation_errors(&ctx);
}

/// A small bumpy sphere (radius 0.5, ~1,000 triangles: levels down to 64 triangles).
fn small_sphere() -> Mesh {
    let (p, i) = common::shapes::sphere(32, 16, [0.0; 3], 0.5);
    common::shapes::mesh_from("sphere", p, i)
}

/// A flat 10 x 10 wall centred on the origin (a few triangles at every level).
fn wall() -> Mesh {
    let p = vec![
        [-5.0, -5.0, 0.0],
        [5.0, -5.0, 0.0],
        [5.0, 5.0, 0.0],
        [-5.0, 5.0, 0.0],
    ];
    common::shapes::mesh_from("wall", p, vec![0, 1, 2, 0, 2, 3])
}

fn gpu_lod(ctx: &vgeo::gpu::Context, meshes: &[Mesh], occlusion: bool) -> Lod {
    let opts = LodOptions {
        occlusion_cull: occlusion,
        ..Default::default()
    };
    Lod::new(ctx, meshes, &opts).expect("gpu lod")
}

fn cpu_lod(ctx: &vgeo::gpu::Context, meshes: &[Mesh]) -> Lod {
    Lod::new(ctx, meshes, &LodOptions::for_mode("lod-cpu").expect("mode")).expect("cpu lod")
}

/// Spheres on a jittered grid in front of the camera at 0.6 to ~12 units, some scaled
/// (non-uniformly), a few outside the view (behind, far to the side).
fn sphere_field() -> Vec<Placement> {
    let mut out = Vec::new();
    for i in 0..6 {
        for j in 0..5 {
            let z = -0.6 * 1.6f64.powi(i) - 0.05 * j as f64;
            let x = (j as f64 - 2.0) * 0.25 * -z;
            let y = ((i + j) % 3) as f64 * 0.1 * -z - 0.1 * -z;
            let s = DVec3::new(1.0 + 0.3 * (j % 2) as f64, 1.0, 1.0 + 0.5 * (i % 2) as f64);
            out.push(Placement {
                mesh: 0,
                transform: DMat4::from_translation(DVec3::new(x, y, z)) * DMat4::from_scale(s),
                color: [0.3 + 0.1 * j as f32, 0.6, 0.8 - 0.1 * i as f32],
            });
        }
    }
    out.push(placement_at(DVec3::new(0.0, 0.0, 3.0)));
    out.push(placement_at(DVec3::new(40.0, 0.0, -2.0)));
    out
}

fn views() -> Vec<Camera> {
    let at =
        |eye: DVec3, target: DVec3| Camera::look_at(eye, target, Vec3::Y, 50f32.to_radians(), 0.01);
    vec![
        camera(),
        at(DVec3::new(0.4, 0.3, 0.5), DVec3::new(-0.2, 0.0, -4.0)),
        at(
            DVec3::new(1.0e5, -2.0e4, 3.0e5),
            DVec3::new(1.0e5 - 1.0, -2.0e4, 3.0e5 - 3.0),
        ),
    ]
}

/// Moves every placement by `offset` (the far-from-origin view sees the same field).
fn shifted(placements: &[Placement], offset: DVec3) -> Vec<Placement> {
    placements
        .iter()
        .map(|p| Placement {
            transform: DMat4::from_translation(offset) * p.transform,
            ..*p
        })
        .collect()
}

#[test]
fn gpu_selection_matches_the_cpu() {
    let ctx = gpu();
    let meshes = vec![small_sphere()];
    let chain = LodChain::build(&meshes[0]);
    let counts = chain.triangle_counts();
    assert!(
        counts[4] < counts[0] / 8,
        "the sphere has a chain: {counts:?}"
    );
    let gpu_lod = gpu_lod(&ctx, &meshes, false);
    let cpu_lod = cpu_lod(&ctx, &meshes);
    let light = Light::default();
    let (w, h) = (64, 48);
    let mut levels_seen = [0u32; LOD_COUNT];
    for (v, cam) in views().iter().enumerate() {
        let placements = if v == 2 {
            shifted(
                &sphere_field(),
                DVec3::new(1.0e5, -2.0e4, 3.0e5) - DVec3::new(0.4, 0.3, 0.5),
            )
        } else {
            sphere_field()
        };
        for tau in [0.5f32, 1.0, 3.0] {
            let (gf, g) = gpu_lod
                .render_with_stats(&placements, cam, &light, (w, h), tau, ShadeMode::Lit)
                .expect("gpu frame");
            let (cf, c) = cpu_lod
                .render_with_stats(&placements, cam, &light, (w, h), tau, ShadeMode::Lit)
                .expect("cpu frame");
            assert_eq!(g.levels.len(), placements.len());
            let ps = vgeo::builder::cut::proj_scale(h as f32, cam.fov_y);
            let mut ties = 0;
            for (i, (gl, cl)) in g.levels.iter().zip(&c.levels).enumerate() {
                let msg = format!("view {v}, {tau} px, instance {i}: gpu {gl:?}, cpu {cl:?}");
                assert_eq!(gl.is_none(), cl.is_none(), "frustum: {msg}");
                let (Some(gl), Some(cl)) = (*gl, *cl) else {
                    continue;
                };
                levels_seen[cl as usize] += 1;
                if gl == cl {
                    continue;
                }
                // A tie: the level between them projects within a hair of the threshold.
                let t = &placements[i].transform;
                let s = vgeo::render::max_axis_scale(t);
                let centre = DVec3::from(Vec3::from_slice(&chain.sphere[..3]));
                let rel = (t.transform_point3(centre) - cam.position).as_vec3();
                let k = gl.max(cl) as usize;
                // Weighted for a small instance, its coverage part whole (select_lod's rule).
                let r = chain.sphere[3] * s;
                let w = vgeo::builder::cut::small_instance_weight(
                    vgeo::builder::cut::lod_error_px(r, rel, r, Vec3::ZERO, ps),
                );
                let e = (chain.errors[k] * w).max(chain.coverages[k]);
                let px = vgeo::builder::cut::lod_error_px(e * s, rel, r, Vec3::ZERO, ps);
                assert!(
                    (px - tau).abs() <= 1e-4 * tau,
                    "{msg}: level {k} at {px} px"
                );
                ties += 1;
            }
            assert!(ties <= 1, "view {v}, {tau} px: {ties} ties");
            assert_eq!(g.frustum_culled, c.frustum_culled);
            assert_eq!((g.post_tested, g.occluded), (0, 0), "occlusion is off");
            if ties == 0 {
                assert_eq!(gf.triangles, cf.triangles, "view {v}, {tau} px");
            }
        }
    }
    eprintln!("levels picked (cpu) over the views: {levels_seen:?}");
    assert!(
        levels_seen.iter().filter(|&&n| n > 0).count() >= 3,
        "{levels_seen:?}"
    );
    assert_no_validation_errors(&ctx);
}

#[test]
fn gpu_image_equals_the_cpu_selection() {
    let ctx = gpu();
    let meshes = vec![small_sphere(), wall()];
    let gpu_lod = gpu_lod(&ctx, &meshes, false);
    let cpu_lod = cpu_lod(&ctx, &meshes);
    let mut placements = sphere_field();
    placements.push(Placement {
        mesh: 1,
        transform: DMat4::from_translation(DVec3::new(0.0, 0.0, -30.0)),
        color: [0.5, 0.5, 0.5],
    });
    let light = Light::default();
    let (w, h) = (80, 60);
    for cam in &views()[..2] {
        for tau in [0.0f32, 1.0, 2.0] {
            let g = gpu_lod
                .render(&placements, cam, &light, w, h, tau)
                .expect("gpu frame");
            let c = cpu_lod
                .render(&placements, cam, &light, w, h, tau)
                .expect("cpu frame");
            assert!(g.covered() > 300, "the field is visible: {}", g.covered());
            assert_eq!(g.triangles, c.triangles, "{tau} px");
            assert!(g.color == c.color, "colour differs at {tau} px");
            assert!(g.depth == c.depth, "depth differs at {tau} px");
        }
    }
    assert_no_validation_errors(&ctx);
}

#[test]
fn hzb_occlusion_keeps_the_image_and_draws_less() {
    let ctx = gpu();
    let meshes = vec![small_sphere(), wall()];
    // A wall filling the view 2 units ahead, eight spheres behind it, two in front.
    let mut placements = vec![Placement {
        mesh: 1,
        transform: DMat4::from_translation(DVec3::new(0.0, 0.0, -2.0)),
        color: [0.6, 0.6, 0.6],
    }];
    for i in 0..8 {
        let x = (i % 4) as f64 - 1.5;
        let y = (i / 4) as f64 - 0.5;
        placements.push(placement_at(DVec3::new(x, y, -4.0 - i as f64)));
    }
    placements.push(placement_at(DVec3::new(-0.4, 0.0, -1.2)));
    placements.push(placement_at(DVec3::new(0.5, 0.2, -1.0)));
    let light = Light::default();
    let (w, h) = (64, 64);
    let occ = gpu_lod(&ctx, &meshes, true);
    let open = gpu_lod(&ctx, &meshes, false);
    let cam = camera();
    let moved = Camera::look_at(
        DVec3::new(0.1, 0.05, 0.0),
        DVec3::new(0.1, 0.0, -1.0),
        Vec3::Y,
        45f32.to_radians(),
        0.01,
    );
    let shade = ShadeMode::Lit;
    let reference = |c: &Camera| {
        open.render_with_stats(&placements, c, &light, (w, h), 1.0, shade)
            .expect("frame without occlusion")
    };
    let (all, all_stats) = reference(&cam);
    assert_eq!(all_stats.drawn(), placements.len() as u32);
    // First frame: no history, everything in the frustum is drawn in the main phase.
    let (f1, s1) = occ
        .render_with_stats(&placements, &cam, &light, (w, h), 1.0, shade)
        .expect("first frame");
    assert_eq!((s1.post_tested, s1.drawn()), (0, placements.len() as u32));
    assert!(f1.color == all.color && f1.depth == all.depth);
    // Second frame (same view), and a third from a moved camera: the previous frame's HZB
    // defers the hidden spheres, this frame's rejects them.
    for (c, name) in [(&cam, "same view"), (&moved, "moved camera")] {
        let (f, s) = occ
            .render_with_stats(&placements, c, &light, (w, h), 1.0, shade)
            .expect("frame with history");
        let (r, _) = reference(c);
        eprintln!("{name}: {s:?}");
        assert_eq!(s.occluded, 8, "{name}: the spheres behind the wall");
        assert_eq!(s.post_tested, 8, "{name}");
        assert_eq!(
            s.drawn(),
            3,
            "{name}: the wall and the two spheres in front"
        );
        assert!(s.occluded_instances[1..9].iter().all(|&o| o), "{name}");
        assert!(f.triangles < r.triangles, "{name}");
        assert!(
            f.color == r.color,
            "{name}: colour differs with occlusion culling"
        );
        assert!(
            f.depth == r.depth,
            "{name}: depth differs with occlusion culling"
        );
    }
    // A sphere that steps out from behind the wall is deferred by the old HZB but drawn by the
    // post phase: the image still matches.
    let mut out = placements.clone();
    out[3] = placement_at(DVec3::new(0.0, 0.0, -1.5));
    let (f, s) = occ
        .render_with_stats(&out, &moved, &light, (w, h), 1.0, shade)
        .expect("frame with a revealed sphere");
    let (r, _) = open
        .render_with_stats(&out, &moved, &light, (w, h), 1.0, shade)
        .expect("reference");
    assert_eq!((s.drawn(), s.occluded), (4, 7), "{s:?}");
    assert!(f.color == r.color && f.depth == r.depth);
    // The same frames back to back in one submission (the benchmark's path timing).
    let times = occ
        .render_path_timed(&placements, &[cam, moved, cam], &light, (w, h), 1.0)
        .expect("path");
    let names: Vec<&str> = times[1].iter().map(|p| p.0.as_str()).collect();
    assert_eq!(
        names,
        [
            "lod_cull",
            "lod",
            "depth_pyramid",
            "lod_cull (post)",
            "lod (post)",
            "shade"
        ]
    );
    assert_no_validation_errors(&ctx);
}

#[test]
fn gpu_frustum_culls_instances_outside_the_view() {
    let ctx = gpu();
    let meshes = vec![small_sphere()];
    let lod = gpu_lod(&ctx, &meshes, true);
    let placements = vec![
        placement_at(DVec3::new(0.0, 0.0, -2.0)),
        placement_at(DVec3::new(0.0, 0.0, 2.0)),
        placement_at(DVec3::new(30.0, 0.0, -2.0)),
        placement_at(DVec3::new(0.0, -30.0, -2.0)),
    ];
    let (f, s) = lod
        .render_with_stats(
            &placements,
            &camera(),
            &Light::default(),
            (32, 32),
            0.0,
            ShadeMode::Lit,
        )
        .expect("frame");
    assert_eq!(s.frustum_culled, 3);
    assert_eq!(s.drawn(), 1);
    assert!(
        s.levels[0] == Some(0) && s.levels[1..].iter().all(|l| l.is_none()),
        "{s:?}"
    );
    assert_eq!(f.triangles, meshes[0].triangle_count() as u64);
    assert!(f.covered() > 20);
    assert_no_validation_errors(&ctx);
}

#[test]
fn the_depth_variant_hzb_equals_the_cpu_pyramid() {
    use vgeo::gpu::{Buffer, Image, MemoryKind, Timer, vk};
    use vgeo::passes::depth_pyramid::DepthPyramid;
    let ctx = gpu();
    let mut seed = 0x9e3779b97f4a7c15u64;
    for (w, h) in [(1, 1), (3, 2), (63, 65), (130, 67), (517, 301)] {
        // Depths in [0, 1] (a D32 copy's range), a quarter of them empty (0).
        let depth: Vec<f32> = (0..w * h)
            .map(|_| {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                let u = (seed >> 40) as f32 / (1u64 << 24) as f32;
                if u < 0.25 { 0.0 } else { u }
            })
            .collect();
        let staging = Buffer::staging(&ctx, "test depth", bytemuck::cast_slice(&depth)).unwrap();
        let image = Image::new(
            &ctx,
            "test depth image",
            w,
            h,
            vk::Format::D32_SFLOAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::TRANSFER_DST,
        )
        .unwrap();
        let copy = Buffer::new(
            &ctx,
            "test depth copy",
            4 * (w * h) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryKind::Gpu,
        )
        .unwrap();
        let pyramid = DepthPyramid::for_depth(&ctx, w, h).unwrap();
        let mut timer = Timer::new(&ctx, 1).unwrap();
        ctx.submit_and_wait("test hzb", |cmd| {
            timer.reset(cmd);
            cmd.copy_buffer_to_image(&staging, &image, &[(0, w, h)]);
            pyramid.record_depth(cmd, &mut timer, &image, &copy);
        })
        .unwrap();
        let gpu_hzb: Vec<f32> = bytemuck::pod_collect_to_vec(&pyramid.hzb.download().unwrap());
        common::assert_hzb_matches_reference(&gpu_hzb, &depth, w, h);
    }
    assert_no_validation_errors(&ctx);
}

/// The GPU selection draws a closed solid seen from outside its box with the faces turned away
/// culled, as vgeo's hardware path drops them: the image equals the CPU selection's (which culls
/// nothing), while outside (mirrored instances excepted: the culling pipeline's front faces wind
/// one way) its instances go to the culling draw, and inside the box or with the near plane
/// cutting into the mesh (its inside showing through the cut) none do.
#[test]
fn closed_solids_seen_from_outside_are_drawn_without_their_faces_turned_away() {
    let ctx = gpu();
    let (spot, _) = vgeo::mesh::load_mesh(&common::assets().join("spot.obj")).expect("spot");
    let chain = LodChain::build(&spot);
    assert!(chain.closed_solid, "spot is a closed solid");
    let sphere = small_sphere();
    let meshes = vec![spot.clone(), sphere];
    let gpu_lod = gpu_lod(&ctx, &meshes, false);
    let cpu_lod = cpu_lod(&ctx, &meshes);
    let [lo, hi] = chain.bounds.map(|b| DVec3::from(b.map(f64::from)));
    let (c, r) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
    let view = |eye: DVec3, target: DVec3, near: f64| {
        Camera::look_at(eye, target, Vec3::Y, 50f32.to_radians(), near as f32)
    };
    let outside = view(
        c + DVec3::new(0.3, 0.2, 1.0).normalize() * 2.5 * r,
        c,
        0.01 * r,
    );
    let inside = view(c, c + DVec3::X, 0.01 * r);
    let sliced = view(DVec3::new(c.x, c.y, hi.z + 0.1 * r), c, 0.5 * r);
    let at = |x: f64| DMat4::from_translation(DVec3::new(x, 0.0, 0.0));
    let mirror = DMat4::from_translation(c)
        * DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0))
        * DMat4::from_translation(-c);
    let spots = |t: DMat4| -> Vec<Placement> {
        [at(0.0) * t, at(0.6 * r) * t]
            .into_iter()
            .map(|transform| Placement {
                mesh: 0,
                transform,
                color: [0.9, 0.8, 0.7],
            })
            .collect()
    };
    let cases = [
        ("outside", outside, spots(DMat4::IDENTITY), 2),
        ("mirrored", outside, spots(mirror), 0),
        ("inside", inside, spots(DMat4::IDENTITY)[..1].to_vec(), 0),
        (
            "near plane cutting in",
            sliced,
            spots(DMat4::IDENTITY)[..1].to_vec(),
            0,
        ),
    ];
    let light = Light::default();
    let (w, h) = (96, 72);
    for (what, cam, placements, culled) in cases {
        for tau in [0.0f32, 1.0] {
            let (g, gs) = gpu_lod
                .render_with_stats(&placements, &cam, &light, (w, h), tau, ShadeMode::Lit)
                .expect("gpu frame");
            let c = cpu_lod
                .render(&placements, &cam, &light, w, h, tau)
                .expect("cpu frame");
            eprintln!(
                "{what}, {tau} px: {} of {} instances without faces turned away, {} pixels covered",
                gs.cull_back,
                gs.drawn(),
                g.covered()
            );
            assert!(
                g.covered() > (w * h / 20) as usize,
                "{what}: the mesh is in view"
            );
            assert_eq!(
                gs.drawn(),
                placements.len() as u32,
                "{what}: every instance drawn"
            );
            assert_eq!(
                gs.cull_back, culled,
                "{what}: instances drawn culling faces"
            );
            assert_eq!(g.triangles, c.triangles, "{what}, {tau} px");
            // Pixels where culling uncovered another surface: a face turned away was the nearest
            // (a fold, or a sliver whose snapped corners turned it). Culling only removes faces,
            // so there the surface is farther (reverse-Z: a smaller depth), and such pixels are
            // rare; a wrong winding would uncover the mesh's inside everywhere.
            let differ = (0..g.depth.len())
                .filter(|&i| {
                    g.depth[i] != c.depth[i]
                        || g.color[4 * i..4 * i + 4] != c.color[4 * i..4 * i + 4]
                })
                .collect::<Vec<_>>();
            eprintln!("  {} pixels differ", differ.len());
            assert!(
                differ.iter().all(|&i| g.depth[i] <= c.depth[i]),
                "{what}, {tau} px: culling brought a surface nearer"
            );
            if culled == 0 {
                assert!(differ.is_empty(), "{what}, {tau} px: the image changed");
            } else {
                assert!(
                    differ.len() * 200 <= g.covered(),
                    "{what}, {tau} px: too many pixels differ"
                );
            }
        }
    }
    assert_no_validation_errors(&ctx);
}
