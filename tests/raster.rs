//! The rasterizers (`raster_sw`, `raster_hw`) and `debug_view` on the GPU (lavapipe in CI, with the
//! validation layer on) against the CPU reference rasterizer, against each other, across runs and
//! far from the origin. The visible list and the counters are written by the test (no culling): all
//! level-0 clusters of two instances of spot, the lists and indirect arguments made on the CPU.
//! The visibility-buffer path is `VisPath::choose` (the image path on GPUs with 64-bit image atomics);
//! the hardware rasterizer runs both its paths where the device has mesh shaders (`hw_paths`), and
//! they must agree bit for bit.

mod common;

use std::sync::OnceLock;

use common::{assert_no_validation_errors, assets, gpu};
use glam::{DMat4, DVec3, Mat4, Vec3, Vec4};
use vgeo::builder::{BuildOptions, BuiltMesh};
use vgeo::camera::Camera;
use vgeo::gpu::{Buffer, Context, MemoryKind, Timer, vk};
use vgeo::passes::cull::Phase;
use vgeo::passes::debug_view::{DebugView, ViewMode};
use vgeo::passes::raster_hw::{HwPath, RasterHw};
use vgeo::passes::raster_sw::RasterSw;
use vgeo::passes::view::{FrameSettings, view_gpu};
use vgeo::passes::{FrameBuffers, VisPath, visbuffer};
use vgeo::reference::{RasterTarget, rasterize};
use vgeo::render::Placement;
use vgeo::scene_gpu::GpuScene;
use vgeo::shared::{
    CullCounters, MAX_CLUSTER_TRIANGLES, RASTER_SW_QUARTER_VERTICES, RASTER_SW_SMALL_VERTICES,
    VISBUFFER_TRIANGLE_BITS, hw_mesh_args,
};

const W: u32 = 128;
const H: u32 = 96;
/// The zooms `very_large_triangles_match_reference` tries, closest first.
const ZOOMS_VERY_LARGE: [f64; 5] = [0.1, 0.15, 0.2, 0.25, 0.3];

/// spot.obj built once for all tests of this file.
fn spot() -> &'static BuiltMesh {
    static SPOT: OnceLock<BuiltMesh> = OnceLock::new();
    SPOT.get_or_init(|| {
        let path = assets().join("spot.obj");
        let (mesh, _) = vgeo::mesh::load_mesh(&path)
            .unwrap_or_else(|e| panic!("cannot load {}: {e}", path.display()));
        vgeo::builder::build(&mesh, &BuildOptions::default()).expect("spot builds")
    })
}

/// `common::shapes::grass_field(2)` built once: clusters of 128 to 170 vertices, which the small
/// path keeps three words a vertex in its half of `raster_sw`'s shared array, and of more.
fn grass() -> &'static BuiltMesh {
    static GRASS: OnceLock<BuiltMesh> = OnceLock::new();
    GRASS.get_or_init(|| {
        let mesh = common::shapes::grass_field(2);
        // At the step ratio 0.5, the default until session 37: its level 3 has clusters of over
        // 127 vertices, which the small path's test below needs (at 0.35 its level 3's
        // clusters in view have fewer).
        vgeo::builder::build(&mesh, &common::options_at_ratio(0.5)).expect("the grass field builds")
    })
}

/// Whether `Split::SmallSw` may put visible entry `i` on the small path: all but the first and
/// every seventh from the fourth, so that both paths run and a workgroup half may have no cluster.
fn small_list_may_take(i: usize) -> bool {
    i != 0 && i % 7 != 3
}

/// Which rasterizer draws a visible entry.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Split {
    AllSw,
    AllHw,
    /// Alternating by visible index (even: SW, odd: HW).
    Mixed,
    /// All SW: most clusters of at most `RASTER_SW_SMALL_VERTICES` vertices at the SW list's
    /// small end (`CullCounters::sw_small_count`, drawn two to a workgroup), most of those of at
    /// most `RASTER_SW_QUARTER_VERTICES` at the HW list's end instead (`sw_quarter_count`, four
    /// to a workgroup), the others at the SW list's front.
    SmallSw,
}

/// Two instances of `mesh` (the second turned, scaled and shifted so that they overlap on screen),
/// offset by `origin`, and a camera framing them from `origin` + the same offset.
/// `zoom` scales the camera's distance to the scene's centre (and the near plane's by its square,
/// keeping the meshes in front of it).
fn scene(mesh: &BuiltMesh, origin: DVec3, zoom: f64) -> (Vec<Placement>, Camera) {
    let p0 = DMat4::from_translation(origin);
    let p1 = DMat4::from_translation(origin + DVec3::new(0.7, 0.05, -0.5))
        * DMat4::from_rotation_y(0.7)
        * DMat4::from_scale(DVec3::splat(0.8));
    let placements = vec![
        Placement {
            mesh: 0,
            transform: p0,
            color: [0.9, 0.6, 0.4],
        },
        Placement {
            mesh: 0,
            transform: p1,
            color: [0.4, 0.7, 0.9],
        },
    ];
    let b = mesh.clusters.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), c| {
            (
                lo.min(Vec3::from(c.bounds_min)),
                hi.max(Vec3::from(c.bounds_max)),
            )
        },
    );
    let lo = b.0.as_dvec3() + origin + DVec3::new(0.0, 0.0, -0.6);
    let hi = b.1.as_dvec3() + origin + DVec3::new(0.7, 0.0, 0.0);
    let mut cam = Camera::frame_bounds(lo, hi, W as f32 / H as f32);
    let centre = (lo + hi) * 0.5;
    cam.position = centre + (cam.position - centre) * zoom;
    cam.near *= (zoom * zoom) as f32;
    (placements, cam)
}

/// The visible list: (instance, global cluster) for each instance's clusters of DAG level `levels[i]`.
fn visible_list(m: &BuiltMesh, levels: &[u32]) -> Vec<[u32; 2]> {
    let mut v = Vec::new();
    for (i, &k) in levels.iter().enumerate() {
        for c in m.level_clusters(k) {
            v.push([i as u32, c]);
        }
    }
    v
}

/// The clip-space positions of the vertices of `visible`'s clusters.
fn clip_vertices<'a>(
    m: &'a BuiltMesh,
    camera: &'a Camera,
    placements: &'a [Placement],
    visible: &'a [[u32; 2]],
) -> impl Iterator<Item = Vec4> + 'a {
    let vp = camera.view_proj(W, H);
    visible.iter().flat_map(move |&[inst, c]| {
        let model = camera.relative_model(&placements[inst as usize].transform);
        let cl = &m.clusters[c as usize];
        (0..cl.vertex_count()).map(move |i| {
            let p = model.transform_point3(Vec3::from(m.position(m.vertex_ref(cl, i))));
            vp * p.extend(1.0)
        })
    })
}

/// The hardware rasterizer's paths this device has: vertex pulling, and mesh shaders where present.
fn hw_paths(ctx: &Context) -> Vec<HwPath> {
    let mut p = vec![HwPath::Vertex];
    if ctx.caps().mesh_shader {
        p.push(HwPath::Mesh);
    } else {
        eprintln!(
            "{}: no mesh shaders, only the vertex path of raster_hw is checked",
            ctx.caps().device_name
        );
    }
    p
}

/// The rasterizers and buffers of one test.
struct Rig {
    ctx: Context,
    mesh: &'static BuiltMesh,
    path: VisPath,
    gpu_scene: GpuScene,
    fb: FrameBuffers,
    sw: RasterSw,
    hw: RasterHw,
    camera: Camera,
    placements: Vec<Placement>,
    visible: Vec<[u32; 2]>,
    /// Clusters the last `render` put at the SW list's small end.
    last_small: u32,
    /// How many went to the quarter path (`CullCounters::sw_quarter_count`) in the last render.
    last_quarter: u32,
}

impl Rig {
    /// The usual view: closer than framing, the meshes fill much of the frame, some parts leave it.
    fn new(origin: DVec3, levels: &[u32]) -> Self {
        Self::with_zoom(origin, levels, 0.6)
    }

    fn with_zoom(origin: DVec3, levels: &[u32], zoom: f64) -> Self {
        Self::of_mesh(spot(), origin, levels, zoom)
    }

    /// Two instances of `mesh` ([`scene`]), their clusters of DAG levels `levels`.
    fn of_mesh(mesh: &'static BuiltMesh, origin: DVec3, levels: &[u32], zoom: f64) -> Self {
        let ctx = gpu();
        let path = VisPath::choose(&ctx).expect("visibility-buffer path");
        let (placements, camera) = scene(mesh, origin, zoom);
        let gpu_scene =
            GpuScene::new(&ctx, std::slice::from_ref(mesh), &placements).expect("scene upload");
        let visible = visible_list(mesh, levels);
        let fb = FrameBuffers::new(&ctx, W, H, path, 64, visible.len() as u32, 2).expect("buffers");
        let sw = RasterSw::new(&ctx, path).expect("raster_sw pipeline");
        let hw = RasterHw::new(&ctx, path, HwPath::Auto).expect("raster_hw pipeline");
        Self {
            ctx,
            mesh,
            path,
            gpu_scene,
            fb,
            sw,
            hw,
            camera,
            placements,
            visible,
            last_small: 0,
            last_quarter: 0,
        }
    }

    /// Makes `raster_hw` draw with `hw_path` from now on.
    fn set_hw_path(&mut self, hw_path: HwPath) {
        self.hw = RasterHw::new(&self.ctx, self.path, hw_path).expect("raster_hw pipeline");
        assert_eq!(self.hw.hw_path(), hw_path);
    }

    /// Writes the view, the lists and the counters, records clear + raster_sw + raster_hw (+ the
    /// debug view) and returns the visibility buffer.
    fn render(&mut self, split: Split, debug: Option<(&DebugView, ViewMode)>) -> Vec<u64> {
        let view = view_gpu(
            &self.camera,
            W,
            H,
            &FrameSettings::default(),
            self.placements.len() as u32,
            self.fb.queue_capacity,
            self.fb.visible_capacity,
        );
        self.fb
            .view
            .write(0, bytemuck::bytes_of(&view))
            .expect("view upload");
        let (mut sw_list, mut hw_list) = (Vec::new(), Vec::new());
        let (mut small, mut quarter) = (Vec::new(), Vec::new());
        for i in 0..self.visible.len() as u32 {
            let to_sw = match split {
                Split::AllSw | Split::SmallSw => true,
                Split::AllHw => false,
                Split::Mixed => i % 2 == 0,
            };
            let cluster = &self.mesh.clusters[self.visible[i as usize][1] as usize];
            // Some small enough for the quarter path on the two-to-a-workgroup one, and some at
            // the front.
            let small_ok = split == Split::SmallSw && small_list_may_take(i as usize);
            if small_ok && cluster.vertex_count() <= RASTER_SW_QUARTER_VERTICES && i % 3 != 2 {
                quarter.push(i)
            } else if small_ok && cluster.vertex_count() <= RASTER_SW_SMALL_VERTICES {
                small.push(i)
            } else if to_sw {
                sw_list.push(i)
            } else {
                hw_list.push(i)
            }
        }
        let (sw_count, hw_count) = (sw_list.len() as u32, hw_list.len() as u32);
        let (small_count, quarter_count) = (small.len() as u32, quarter.len() as u32);
        self.last_small = small_count;
        self.last_quarter = quarter_count;
        // The small ones from the SW list's end backwards, the quarter ones from the HW list's
        // (as the cull writes them).
        let cap = self.fb.visible_capacity as usize;
        sw_list.resize(cap, 0);
        hw_list.resize(cap, 0);
        for (j, &v) in small.iter().enumerate() {
            sw_list[cap - 1 - j] = v;
        }
        for (j, &v) in quarter.iter().enumerate() {
            hw_list[cap - 1 - j] = v;
        }
        let small_groups = small_count.div_ceil(2);
        let quarter_groups = quarter_count.div_ceil(4);
        let counters = CullCounters {
            visible_count: self.visible.len() as u32,
            sw_count: sw_count + small_count + quarter_count,
            sw_small_count: small_count,
            sw_quarter_count: quarter_count,
            sw_quarter_groups: quarter_groups,
            hw_count,
            sw_dispatch: [small_groups + quarter_groups + sw_count, 1, 1, small_groups],
            hw_draw: [MAX_CLUSTER_TRIANGLES * 3, hw_count, 0, 0],
            hw_mesh: hw_mesh_args(hw_count),
            ..Default::default()
        };
        let ctx = &self.ctx;
        let staging = |name: &str, bytes: &[u8]| {
            let mut b = Buffer::new(
                ctx,
                name,
                bytes.len() as u64,
                vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryKind::Upload,
            )
            .expect("staging buffer");
            b.write(0, bytes).expect("staging write");
            b
        };
        // The GPU's entries name a cluster by the pool word of its data, as the cull writes them.
        let words: Vec<[u32; 2]> = self
            .visible
            .iter()
            .map(|&[instance, cluster]| {
                let word = self
                    .gpu_scene
                    .cluster_word(cluster)
                    .expect("cluster in the pool");
                [instance, word]
            })
            .collect();
        let s_visible = staging("test visible", bytemuck::cast_slice(&words));
        let s_sw = staging("test sw list", bytemuck::cast_slice(&sw_list));
        let s_hw = staging("test hw list", bytemuck::cast_slice(&hw_list));
        let mut timer = Timer::new(ctx, 8).expect("timer");
        let fb = &self.fb;
        let (sw, hw, scene) = (&self.sw, &self.hw, &self.gpu_scene);
        ctx.submit_and_wait("raster test frame", |cmd| {
            use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
            timer.reset(cmd);
            cmd.copy_buffer(&s_visible, &fb.visible, 8 * self.visible.len() as u64);
            cmd.copy_buffer(&s_sw, &fb.sw_list, 4 * cap as u64);
            cmd.copy_buffer(&s_hw, &fb.hw_list, 4 * cap as u64);
            cmd.update_buffer(&fb.counters, 0, bytemuck::bytes_of(&counters));
            visbuffer::clear(cmd, fb);
            let shaders = S::COMPUTE_SHADER | hw.input_stages();
            cmd.barrier(
                (S::ALL_TRANSFER, A::TRANSFER_WRITE),
                (
                    shaders | S::DRAW_INDIRECT,
                    A::SHADER_STORAGE_READ
                        | A::SHADER_STORAGE_WRITE
                        | A::UNIFORM_READ
                        | A::INDIRECT_COMMAND_READ,
                ),
            );
            sw.record(cmd, &mut timer, scene, fb, Phase::Main);
            cmd.barrier(
                (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
                (
                    S::FRAGMENT_SHADER,
                    A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE,
                ),
            );
            hw.record(cmd, &mut timer, scene, fb, Phase::Main);
            if let Some((dv, mode)) = debug {
                cmd.barrier(
                    (S::FRAGMENT_SHADER, A::SHADER_STORAGE_WRITE),
                    (S::COMPUTE_SHADER, A::SHADER_STORAGE_READ),
                );
                dv.record(cmd, &mut timer, scene, fb, mode, Vec3::new(0.4, 1.0, 0.6))
                    .expect("debug_view record");
            }
        })
        .expect("frame");
        assert_no_validation_errors(&self.ctx);
        visbuffer::download(&self.fb).expect("visbuffer download")
    }

    /// The CPU reference of the same visible list: ids are `visible index << 7 | triangle`.
    fn reference(&self) -> RasterTarget {
        let m = self.mesh;
        let positions = m.positions();
        let vp = self.camera.view_proj(W, H);
        let mut target = RasterTarget::new(W, H);
        let mut tris = Vec::new();
        for (vi, &[inst, cluster]) in self.visible.iter().enumerate() {
            let model: Mat4 = self
                .camera
                .relative_model(&self.placements[inst as usize].transform);
            for (t, tri) in m.cluster_triangles(cluster as usize).iter().enumerate() {
                let p = tri.map(|v| model.transform_point3(Vec3::from(positions[v as usize])));
                tris.push((p, (vi as u32) << VISBUFFER_TRIANGLE_BITS | t as u32));
            }
        }
        rasterize(&mut target, &vp, tris);
        target
    }
}

/// GPU visibility buffer vs the reference: (coverage agreement, depth agreement among pixels both
/// cover, id agreement among those, largest relative depth difference, pixels covered by both).
fn compare(gpu: &[u64], r: &RasterTarget) -> (f64, f64, f64, f32, usize) {
    let (mut same_cover, mut both, mut depth_ok, mut id_ok) = (0, 0, 0, 0);
    let mut max_rel = 0f32;
    for (i, &g) in gpu.iter().enumerate() {
        let g = visbuffer::unpack(g);
        let covered = r.id[i] != u32::MAX;
        if g.is_some() == covered {
            same_cover += 1;
        }
        if let (Some((d, vis, tri)), true) = (g, covered) {
            both += 1;
            let rel = (d - r.depth[i]).abs() / r.depth[i].max(1e-30);
            max_rel = max_rel.max(rel);
            if rel <= 1e-4 {
                depth_ok += 1;
            }
            if (vis << VISBUFFER_TRIANGLE_BITS | tri) == r.id[i] {
                id_ok += 1;
            }
        }
    }
    let n = gpu.len() as f64;
    let b = both.max(1) as f64;
    (
        same_cover as f64 / n,
        depth_ok as f64 / b,
        id_ok as f64 / b,
        max_rel,
        both,
    )
}

fn check_against_reference(split: Split) {
    check_rig_against_reference(&mut Rig::new(DVec3::ZERO, &[0, 0]), split, 0.999);
}

/// `min_depth`: share of pixels whose depth must be within 1e-4 relative of the reference's.
fn check_rig_against_reference(rig: &mut Rig, split: Split, min_depth: f64) {
    let gpu = rig.render(split, None);
    let r = rig.reference();
    let (cover, depth, ids, max_rel, both) = compare(&gpu, &r);
    eprintln!(
        "{split:?} ({:?} path): coverage agreement {cover:.5}, depth within 1e-4 {depth:.5} \
         (max rel diff {max_rel:.2e}), same id {ids:.5}, {both} of {} pixels covered by both",
        rig.path,
        gpu.len()
    );
    assert!(
        both as u32 > W * H / 4,
        "the scene should cover a good part of the frame: {both} pixels"
    );
    assert!(both < gpu.len(), "the scene should not cover every pixel");
    assert!(
        cover >= 0.999,
        "{split:?}: coverage agreement {cover:.5} < 99.9%"
    );
    assert!(
        depth >= min_depth,
        "{split:?}: depth agreement {depth:.5} < {min_depth}"
    );
    assert!(
        max_rel < 2e-3,
        "{split:?}: largest relative depth difference {max_rel:.2e}"
    );
    assert!(ids >= 0.99, "{split:?}: id agreement {ids:.5} < 99%");
}

#[test]
fn sw_matches_reference() {
    check_against_reference(Split::AllSw);
}

#[test]
fn hw_matches_reference() {
    let mut rig = Rig::new(DVec3::ZERO, &[0, 0]);
    for p in hw_paths(&rig.ctx) {
        rig.set_hw_path(p);
        eprintln!("raster_hw {p:?} path:");
        check_rig_against_reference(&mut rig, Split::AllHw, 0.999);
    }
}

/// The coarsest DAG level close up: triangles of tens of pixels, which `raster_sw` walks by scanline.
#[test]
fn large_triangles_match_reference() {
    // The coarsest level that still has the silhouette (the root chain below it has few
    // triangles that cover little).
    let top = spot()
        .stats
        .levels
        .iter()
        .rposition(|l| l.triangles >= 90)
        .expect("a level with 90 triangles") as u32;
    let mut rig = Rig::with_zoom(DVec3::ZERO, &[top, top], 0.5);
    let tris: usize = rig
        .visible
        .iter()
        .map(|&[_, c]| spot().clusters[c as usize].triangle_count() as usize)
        .sum();
    eprintln!("level {top}: {tris} triangles");
    assert!(
        tris < 1000,
        "level {top} should be coarse: {tris} triangles"
    );
    // Large, steep triangles: the GPU evaluates the depth plane in f32 from vertices far from the
    // pixel, so a few grazing pixels differ from the reference by up to ~1e-3 relative (measured:
    // 0.14 % of pixels over 1e-4, max 1.3e-3). SW and HW still agree bit for bit (below).
    check_rig_against_reference(&mut rig, Split::AllSw, 0.995);
    let sw = rig.render(Split::AllSw, None);
    // Coverage is exact: the same snapped vertices, the same top-left rule. Here raster_sw solves
    // most of it by scanline spans (a float estimate made exact, first_inside / last_inside), so
    // every pixel's coverage and triangle must be the reference's, not 99.9 % of them.
    let (cover, _, ids, _, _) = compare(&sw, &rig.reference());
    assert!(
        cover == 1.0 && ids == 1.0,
        "large triangles by scanline: coverage {cover}, ids {ids} (exact expected)"
    );
    let mut first_hw: Option<Vec<u64>> = None;
    for p in hw_paths(&rig.ctx) {
        rig.set_hw_path(p);
        check_rig_against_reference(&mut rig, Split::AllHw, 0.995);
        let hw = rig.render(Split::AllHw, None);
        let differ = (0..sw.len()).filter(|&i| sw[i] != hw[i]).count();
        eprintln!("large triangles, SW vs HW ({p:?} path): {differ} pixels differ");
        assert!(differ as f64 <= 1e-4 * sw.len() as f64);
        match &first_hw {
            None => first_hw = Some(hw),
            Some(v) => assert!(*v == hw, "large triangles: the HW paths differ"),
        }
    }
}

/// The root chain's few triangles close up, their vertices far off the 128 x 96 frame: `raster_sw`
/// solves their rows (int64 edge functions, the span's float estimate made exact) over boxes
/// clamped to the screen. Coverage and triangles exactly the reference's. (Checked: a span one
/// pixel too long in `raster_row`'s loop fails it.)
#[test]
fn very_large_triangles_match_reference() {
    let levels = spot().stats.levels.len() as u32;
    let root = levels - 1;
    // The closest zoom at which the root lies wholly in front of the near plane: `raster_sw`
    // skips a triangle that crosses it (`near_plane_crossing` checks that case), and a close
    // camera can stand inside a coarse root's hull.
    let visible = visible_list(spot(), &[root, root]);
    let zoom = ZOOMS_VERY_LARGE
        .into_iter()
        .find(|&z| {
            let (placements, camera) = scene(spot(), DVec3::ZERO, z);
            clip_vertices(spot(), &camera, &placements, &visible).all(|c| c.z <= c.w)
        })
        .expect("a zoom with the root in front of the near plane");
    let mut rig = Rig::with_zoom(DVec3::ZERO, &[root, root], zoom);
    // Very large: some vertex far off the frame (beyond three frame widths from its centre).
    let far = clip_vertices(rig.mesh, &rig.camera, &rig.placements, &rig.visible)
        .map(|c| (c.x / c.w).abs().max((c.y / c.w).abs()))
        .fold(0.0, f32::max);
    eprintln!("zoom {zoom}: farthest vertex at {far:.1} half-frames from the centre");
    assert!(
        far > 3.0,
        "the root's vertices should leave the frame far: {far}"
    );
    let sw = rig.render(Split::AllSw, None);
    let (cover, depth, ids, _, both) = compare(&sw, &rig.reference());
    eprintln!("root close up: {both} pixels covered by both, depth within 1e-4 {depth:.5}");
    assert!(
        both > 500,
        "the root should cover a part of the frame: {both} pixels"
    );
    assert!(
        cover == 1.0 && ids == 1.0 && depth >= 0.995,
        "very large triangles: coverage {cover}, ids {ids} (exact expected), depth {depth}"
    );
}

/// A camera so close that triangles cross the near plane: HW clips them like the reference, SW
/// skips them (only ever covering a subset of the reference's pixels, never garbage).
#[test]
fn near_plane_crossing() {
    let mut rig = Rig::with_zoom(DVec3::ZERO, &[0, 0], 0.4);
    // The near plane through the middle of the nearer instance.
    rig.camera.near = rig.camera.position.length() as f32 * 0.85;
    let r = rig.reference();
    let behind = clip_vertices(rig.mesh, &rig.camera, &rig.placements, &rig.visible)
        .filter(|c| c.z > c.w)
        .count();
    eprintln!("{behind} cluster vertices behind the near plane");
    assert!(
        behind > 0,
        "the camera should cut the near plane through the mesh"
    );
    let mut first_hw: Option<Vec<u64>> = None;
    for p in hw_paths(&rig.ctx) {
        rig.set_hw_path(p);
        let hw = rig.render(Split::AllHw, None);
        let (cover, depth, _, max_rel, both) = compare(&hw, &r);
        eprintln!(
            "near plane, HW ({p:?} path): coverage agreement {cover:.5}, depth within 1e-4 {depth:.5} (max {max_rel:.2e}), {both} covered"
        );
        assert!(both as u32 > W * H / 4);
        assert!(cover >= 0.999, "HW coverage agreement {cover:.5}");
        // Clipped triangles too: their depth comes from their clip-space vertices, not from how
        // a pipeline clipped them (`clipped_depth`), so the paths agree bit for bit.
        match &first_hw {
            None => first_hw = Some(hw),
            Some(v) => {
                let differ = (0..hw.len()).filter(|&i| v[i] != hw[i]).count();
                eprintln!("near plane, the HW paths: {differ} pixels differ");
                assert_eq!(differ, 0, "near plane: the HW paths differ");
            }
        }
    }
    let sw = rig.render(Split::AllSw, None);
    let outside = (0..sw.len())
        .filter(|&i| sw[i] != 0 && r.id[i] == u32::MAX)
        .count();
    let missing = (0..sw.len())
        .filter(|&i| sw[i] == 0 && r.id[i] != u32::MAX)
        .count();
    eprintln!("near plane, SW: {outside} pixels outside the reference, {missing} skipped");
    assert_eq!(outside, 0, "SW drew pixels the reference does not cover");
}

#[test]
fn sw_and_hw_agree_and_runs_are_deterministic() {
    let mut rig = Rig::new(DVec3::ZERO, &[0, 0]);
    let paths = hw_paths(&rig.ctx);
    let mut by_path = Vec::new();
    for &p in &paths {
        rig.set_hw_path(p);
        sw_and_hw_agree(&mut rig);
        by_path.push((
            p,
            rig.render(Split::AllHw, None),
            rig.render(Split::Mixed, None),
        ));
    }
    // The mesh path equals the vertex path bit for bit: same coverage, same depth, same ids.
    for w in by_path.windows(2) {
        let ((pa, hw_a, mixed_a), (pb, hw_b, mixed_b)) = (&w[0], &w[1]);
        let differ = (0..hw_a.len()).filter(|&i| hw_a[i] != hw_b[i]).count();
        eprintln!("all-HW, {pa:?} vs {pb:?} path: {differ} pixels differ");
        assert_eq!(differ, 0, "all-HW: the {pa:?} and {pb:?} paths differ");
        assert!(
            mixed_a == mixed_b,
            "mixed: the {pa:?} and {pb:?} paths differ"
        );
    }
}

/// All-SW against all-HW (the rig's HW path), then determinism of each and of a mixed split.
fn sw_and_hw_agree(rig: &mut Rig) {
    let sw = rig.render(Split::AllSw, None);
    let hw = rig.render(Split::AllHw, None);
    let n = sw.len();
    let differ: Vec<usize> = (0..n).filter(|&i| sw[i] != hw[i]).collect();
    let (mut cover_only, mut depth_only, mut id_only) = (0, 0, 0);
    for &i in &differ {
        match (visbuffer::unpack(sw[i]), visbuffer::unpack(hw[i])) {
            (Some((ds, ..)), Some((dh, ..))) if ds == dh => id_only += 1,
            (Some(_), Some(_)) => depth_only += 1,
            _ => cover_only += 1,
        }
    }
    let covered = sw.iter().filter(|&&v| v != 0).count();
    eprintln!(
        "SW vs HW ({:?} path, {:?} HW path): {} of {n} pixels differ ({cover_only} coverage, \
         {depth_only} depth, {id_only} id only); {covered} covered",
        rig.path,
        rig.hw.hw_path(),
        differ.len()
    );
    assert!(covered as u32 > W * H / 4);
    assert!(
        differ.len() as f64 <= 1e-4 * n as f64,
        "SW and HW differ on {} pixels: {:?}",
        differ.len(),
        &differ[..differ.len().min(10)]
    );
    // Determinism: the same frame again, bit for bit, on each rasterizer and mixed.
    assert_eq!(sw, rig.render(Split::AllSw, None), "SW run differs");
    assert_eq!(hw, rig.render(Split::AllHw, None), "HW run differs");
    let mixed = rig.render(Split::Mixed, None);
    assert_eq!(mixed, rig.render(Split::Mixed, None), "mixed run differs");
    let mixed_diff = (0..n).filter(|&i| mixed[i] != sw[i]).count();
    eprintln!("mixed SW/HW vs all-SW: {mixed_diff} pixels differ");
    assert!(mixed_diff as f64 <= 1e-4 * n as f64);
}

#[test]
fn far_from_origin_renders_the_same() {
    let mut near = Rig::new(DVec3::ZERO, &[0, 0]);
    let mut far = Rig::new(DVec3::new(1.0e6, -1.0e6, 1.0e6), &[0, 0]);
    for split in [Split::AllSw, Split::AllHw] {
        let a = near.render(split, None);
        let b = far.render(split, None);
        let differ = (0..a.len()).filter(|&i| a[i] != b[i]).count();
        let max_rel = a
            .iter()
            .zip(&b)
            .filter_map(
                |(&x, &y)| match (visbuffer::unpack(x), visbuffer::unpack(y)) {
                    (Some((dx, ..)), Some((dy, ..))) => Some((dx - dy).abs() / dx),
                    _ => None,
                },
            )
            .fold(0f32, f32::max);
        eprintln!(
            "{split:?}: origin vs 1e6 away: {differ} of {} pixels differ, max rel depth diff {max_rel:.2e}",
            a.len()
        );
        assert!(a.iter().filter(|&&v| v != 0).count() as u32 > W * H / 4);
        assert!(
            differ as f64 <= 1e-3 * a.len() as f64,
            "{split:?}: {differ} pixels differ"
        );
        assert!(max_rel < 1e-4, "{split:?}: depth differs by {max_rel:e}");
    }
}

#[test]
fn every_view_mode_renders() {
    // Instance 0 at level 0, instance 1 at level 1, mixed SW/HW: every mode has something to show.
    let mut rig = Rig::new(DVec3::ZERO, &[0, 1]);
    let dv = DebugView::new(&rig.ctx, &rig.fb).expect("debug_view");
    for mode in ViewMode::ALL {
        if mode == ViewMode::Overdraw {
            // Needs the frame's overdraw counters, which this rig does not keep (tests/views.rs).
            continue;
        }
        rig.render(Split::Mixed, Some((&dv, mode)));
        let img = dv.download().expect("debug image");
        assert_eq!(img.len(), (W * H * 4) as usize);
        if let Ok(dir) = std::env::var("VGEO_TEST_DUMP") {
            let path = std::path::Path::new(&dir).join(format!("raster_{}.png", mode.name()));
            image::save_buffer(&path, &img, W, H, image::ColorType::Rgba8).expect("save dump");
        }
        let distinct: std::collections::BTreeSet<&[u8]> = img.chunks(4).collect();
        let bg = img[..4].to_vec();
        let background = img.chunks(4).filter(|c| *c == bg.as_slice()).count();
        eprintln!(
            "{mode:?}: {} distinct colours, {background} background pixels",
            distinct.len()
        );
        let min_colours = match mode {
            // Every page resident: one colour (resident) and the background.
            ViewMode::Residency => 2,
            ViewMode::Lod | ViewMode::HwSw | ViewMode::Instances | ViewMode::Groups => 3,
            _ => 20,
        };
        assert!(
            distinct.len() >= min_colours,
            "{mode:?}: only {} distinct colours",
            distinct.len()
        );
        assert!(
            background > 0 && background < img.len() / 4,
            "{mode:?}: the corner colour should be background, not everywhere"
        );
        assert_ne!(
            ViewMode::parse(mode.name()),
            None,
            "{mode:?}: name does not parse"
        );
    }
    assert_no_validation_errors(&rig.ctx);
}

/// `raster_sw`'s paths for small clusters (`CullCounters::sw_small_count`: two clusters to a
/// workgroup, two triangles an invocation; `sw_quarter_count`: four to a workgroup, up to four
/// triangles an invocation; every triangle walked by its own invocation) draw what its path for
/// the others draws, bit for bit: on the usual view (level 0) and on coarse levels whose large
/// triangles the other path shares across the workgroup, with all three in the same dispatch.
#[test]
fn the_small_clusters_path_draws_what_the_other_sw_path_draws() {
    for levels in [[0u32, 0], [3, 4]] {
        let mut rig = Rig::new(DVec3::ZERO, &levels);
        let sw = rig.render(Split::AllSw, None);
        let small = rig.render(Split::SmallSw, None);
        let n = rig.visible.len() as u32;
        let (halves, quarters) = (rig.last_small, rig.last_quarter);
        eprintln!(
            "levels {levels:?}: {halves} of {n} clusters on the small path, {quarters} on the \
             quarter path"
        );
        assert!(halves > 0 && halves + quarters < n, "both SW paths run");
        // The coarse levels' clusters all have over RASTER_SW_QUARTER_VERTICES vertices.
        if levels == [0, 0] {
            assert!(quarters > 0, "the quarter path runs");
            assert!(
                halves % 2 == 1 || quarters % 4 != 0,
                "a workgroup part has no cluster"
            );
        }
        assert!(sw.iter().filter(|&&p| p != 0).count() as u32 > W * H / 8);
        assert!(small == sw, "the small clusters' path draws differently");
    }
    assert_no_validation_errors(&gpu());
}

/// The small path draws clusters of up to `RASTER_SW_SMALL_VERTICES` vertices (two to a workgroup,
/// each half of the shared array holding one cluster's) as the other SW path draws them, bit for
/// bit: the grass field's levels, whose clusters of 128 to 170 vertices the small path took only
/// from session 26 on (they overran a half of 127 before).
#[test]
fn clusters_of_many_vertices_on_the_small_path_draw_what_the_other_sw_path_draws() {
    let wide = |c: u32| (128..=RASTER_SW_SMALL_VERTICES).contains(&c);
    for levels in [[0u32, 1], [2, 0], [1, 3]] {
        let mut rig = Rig::of_mesh(grass(), DVec3::ZERO, &levels, 0.6);
        let sw = rig.render(Split::AllSw, None);
        let small = rig.render(Split::SmallSw, None);
        let wide_small = rig
            .visible
            .iter()
            .enumerate()
            .filter(|&(i, &[_, c])| {
                small_list_may_take(i) && wide(grass().clusters[c as usize].vertex_count())
            })
            .count();
        eprintln!(
            "levels {levels:?}: {} of {} clusters on the small path, {wide_small} of 128 to {} \
             vertices",
            rig.last_small,
            rig.visible.len(),
            RASTER_SW_SMALL_VERTICES
        );
        assert!(
            wide_small > 0,
            "no cluster of over 127 vertices went to the small path"
        );
        let covered = sw.iter().filter(|&&p| p != 0).count() as u32;
        assert!(covered > W * H / 50, "the blades cover {covered} pixels");
        assert!(small == sw, "the small clusters' path draws differently");
    }
    assert_no_validation_errors(&gpu());
}

/// The other SW path's shared pass takes a large triangle's corners from its list entry (8 bits
/// each): on the grass field close up, where triangles with corners past 127 have boxes of many
/// pixels, all-SW draws what all-HW draws (its corners from the cluster's own code).
#[test]
fn large_triangles_of_clusters_of_many_vertices_match_hw() {
    let mut rig = Rig::of_mesh(grass(), DVec3::ZERO, &[0, 0], 0.15);
    // Triangles with a corner past 127 that cover over RASTER_SW_BIG_BOX_PIXELS (64) pixels, so
    // that their box does too and the shared pass takes them (the CPU reference's coverage).
    let positions = grass().positions();
    let mut tris = Vec::new();
    for &[inst, ci] in &rig.visible {
        let model: Mat4 = rig
            .camera
            .relative_model(&rig.placements[inst as usize].transform);
        let local = grass().cluster_local_triangles(&grass().clusters[ci as usize]);
        for (t, g) in local.iter().zip(grass().cluster_triangles(ci as usize)) {
            if t.iter().any(|&k| k > 127) {
                let p = g.map(|v| model.transform_point3(Vec3::from(positions[v as usize])));
                tris.push((p, tris.len() as u32));
            }
        }
    }
    let mut pixels = vec![0u32; tris.len()];
    vgeo::reference::raster::for_each_fragment(
        W,
        H,
        &rig.camera.view_proj(W, H),
        Default::default(),
        tris,
        |f| pixels[f.id as usize] += 1,
    );
    let large_high = pixels.iter().filter(|&&n| n > 64).count();
    eprintln!("{large_high} large triangles with a corner past 127");
    assert!(large_high > 0, "no large triangle with a corner past 127");
    let sw = rig.render(Split::AllSw, None);
    let hw = rig.render(Split::AllHw, None);
    let differ = sw.iter().zip(&hw).filter(|(a, b)| a != b).count();
    let covered = sw.iter().filter(|&&p| p != 0).count();
    eprintln!(
        "SW vs HW: {differ} of {} pixels differ, {covered} covered",
        sw.len()
    );
    assert!(
        covered as u32 > W * H / 10,
        "the blades cover {covered} pixels"
    );
    assert!(
        differ as f64 <= 1e-4 * sw.len() as f64,
        "SW and HW differ on {differ} pixels"
    );
    assert_no_validation_errors(&gpu());
}

/// The visible list names a cluster by the pool word of its data; the CPU's read-back turns every
/// cluster's word back into its index, keeps unused slots (all ones), and refuses a word inside a
/// cluster's data (no cluster starts there) instead of naming a wrong cluster.
#[test]
fn visible_words_turn_back_into_cluster_indices() {
    let rig = Rig::new(DVec3::ZERO, &[0, 0]);
    let scene = &rig.gpu_scene;
    let n = spot().clusters.len() as u32;
    let mut entries: Vec<[u32; 2]> = (0..n)
        .map(|c| {
            [
                c % 2,
                scene.cluster_word(c).expect("every page is in the pool"),
            ]
        })
        .collect();
    entries.push([u32::MAX; 2]);
    scene
        .clusters_at_words(&mut entries)
        .expect("words of clusters");
    for c in 0..n {
        assert_eq!(entries[c as usize], [c % 2, c]);
    }
    assert_eq!(entries[n as usize], [u32::MAX; 2]);
    let inside = scene.cluster_word(1).expect("in the pool") + 1;
    assert!(scene.clusters_at_words(&mut [[0, inside]]).is_err());
    assert!(scene.clusters_at_words(&mut [[0, u32::MAX - 1]]).is_err());
    assert_eq!(scene.cluster_word(n), None, "no such cluster");
}
