//! A scene that changes (lavapipe, validation on): instances moved, removed and added and meshes
//! added after the first frame are drawn in that very frame exactly as a renderer built from
//! scratch with the final scene draws them; stale handles are errors; buffers and capacities grow.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

use common::shapes::{mesh_from, sphere};
use common::{assert_no_validation_errors, gpu};
use glam::{DMat4, DVec3, Vec3};
use vgeo::builder::{BuildOptions, BuiltMesh, build};
use vgeo::camera::Camera;
use vgeo::frame::{VgeoFrame, VgeoRenderer};
use vgeo::gpu::Context;
use vgeo::mesh::Material;
use vgeo::passes::debug_view::ViewMode;
use vgeo::passes::view::FrameSettings;
use vgeo::render::{Light, Placement};
use vgeo::scene_gpu::{InstanceDesc, InstanceHandle, MeshHandle, SceneError};

/// Counts heap allocations of the threads that switch counting on (the other tests' threads
/// allocate concurrently and are not counted).
struct CountingAlloc;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
}

// SAFETY: forwards to the system allocator; the counter and the thread-local flag do not allocate.
unsafe impl GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.with(|c| c.get()) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: the caller's layout is passed on unchanged.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System.alloc` with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if COUNTING.with(|c| c.get()) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: as for `alloc` and `dealloc`.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

/// Heap allocations made by `f` on this thread.
fn allocations(f: impl FnOnce()) -> u64 {
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    COUNTING.with(|c| c.set(true));
    f();
    COUNTING.with(|c| c.set(false));
    ALLOCATIONS.load(Ordering::Relaxed) - before
}

const W: u32 = 96;
const H: u32 = 72;

/// A small bumpy sphere of radius `r` with one material of colour `rgb`.
fn ball(name: &str, seg: u32, r: f32, rgb: [f32; 3]) -> BuiltMesh {
    let (p, i) = sphere(seg, seg / 2, [0.0; 3], r);
    let mut m = mesh_from(name, p, i);
    m.materials = vec![Material {
        name: format!("{name} material"),
        base_color: [rgb[0], rgb[1], rgb[2], 1.0],
        ..Material::default()
    }];
    build(&m, &BuildOptions::default()).expect("mesh builds")
}

fn at(x: f64, y: f64, z: f64) -> DMat4 {
    DMat4::from_translation(DVec3::new(x, y, z))
}

fn camera() -> Camera {
    Camera::look_at(
        DVec3::new(0.0, 0.0, 9.0),
        DVec3::ZERO,
        Vec3::Y,
        50f32.to_radians(),
        0.1,
    )
}

/// The pixel (row-major index) where the camera sees the point (x, y, 0).
fn pixel(x: f64, y: f64) -> usize {
    let half_h = 9.0 * (25f64).to_radians().tan();
    let half_w = half_h * W as f64 / H as f64;
    let px = (W as f64 * 0.5 * (1.0 + x / half_w)) as usize;
    let py = (H as f64 * 0.5 * (1.0 - y / half_h)) as usize;
    py * W as usize + px
}

fn frame(r: &mut VgeoRenderer, mode: ViewMode) -> VgeoFrame {
    let f = r
        .render(
            &camera(),
            W,
            H,
            &FrameSettings::default(),
            mode,
            &Light::default(),
        )
        .expect("frame renders");
    f.check().expect("no overflow, no watchdog");
    f
}

/// A renderer built from scratch with `meshes` and `placements`, one frame of `mode`.
fn fresh(
    ctx: &Context,
    meshes: &[&BuiltMesh],
    placements: &[Placement],
    mode: ViewMode,
) -> VgeoFrame {
    let mut r = VgeoRenderer::new(ctx, meshes, placements).expect("renderer");
    frame(&mut r, mode)
}

/// Same depth and colour at every pixel.
fn assert_same(what: &str, got: &VgeoFrame, want: &VgeoFrame) {
    let depth = (0..got.frame.depth.len())
        .filter(|&i| got.frame.depth[i].to_bits() != want.frame.depth[i].to_bits())
        .count();
    let colour = got
        .frame
        .color
        .chunks_exact(4)
        .zip(want.frame.color.chunks_exact(4))
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        want.frame.covered() > 100,
        "{what}: the reference shows too little ({} px)",
        want.frame.covered()
    );
    assert_eq!(
        (depth, colour),
        (0, 0),
        "{what}: pixels whose depth / colour differ from a renderer built with the final scene"
    );
}

/// Pixels whose visible instance (dense slot) is `slot`.
fn pixels_of(f: &VgeoFrame, slot: u32) -> usize {
    f.visbuffer
        .iter()
        .filter(|&&v| f.resolve(v).is_some_and(|(e, _)| e[0] == slot))
        .count()
}

fn place(mesh: u32, t: DMat4, color: [f32; 3]) -> Placement {
    Placement {
        mesh,
        transform: t,
        color,
    }
}

#[test]
fn moved_removed_added_in_frame_k() {
    let ctx = gpu();
    let a = ball("a", 24, 1.0, [0.9, 0.3, 0.2]);
    let b = ball("b", 16, 0.7, [0.2, 0.5, 0.9]);
    let start = vec![
        place(0, at(-2.5, 0.0, 0.0), [0.9, 0.9, 0.9]),
        place(1, at(0.0, 0.0, 0.0), [0.8, 0.7, 0.6]),
        place(0, at(2.5, 0.0, 0.0), [0.6, 0.8, 0.7]),
    ];
    let mut r = VgeoRenderer::new(&ctx, &[&a, &b], &start).expect("renderer");
    let h: Vec<InstanceHandle> = (0..3)
        .map(|i| r.scene.instance_handle(i).expect("handle"))
        .collect();
    let f0 = frame(&mut r, ViewMode::Lambert);
    assert_same(
        "frame 0",
        &f0,
        &fresh(&ctx, &[&a, &b], &start, ViewMode::Lambert),
    );

    // Frame 1: the middle instance moves up; drawn there in this frame.
    let moved = at(0.0, 1.8, -1.0);
    r.scene.set_transform(h[1], &moved).expect("live handle");
    let f1 = frame(&mut r, ViewMode::Lambert);
    let mut now = start.clone();
    now[1].transform = moved;
    assert_same(
        "moved",
        &f1,
        &fresh(&ctx, &[&a, &b], &now, ViewMode::Lambert),
    );
    assert_ne!(
        f0.frame.depth, f1.frame.depth,
        "the move must change the image"
    );
    // The pixel at the view's centre showed instance 1 and is empty now.
    let centre = pixel(0.0, 0.0);
    assert_eq!(f0.resolve(f0.visbuffer[centre]).map(|e| e.0[0]), Some(1));
    assert_eq!(f1.visbuffer[centre], 0);

    // Frame 2: the first instance is removed (the last one takes its dense slot).
    r.scene.remove_instance(h[0]).expect("live handle");
    assert_eq!(r.scene.instance_count, 2);
    assert_eq!(r.scene.instance_slot(h[2]).expect("live"), 0);
    let f2 = frame(&mut r, ViewMode::Lambert);
    let now2 = vec![now[2], now[1]];
    assert_same(
        "removed",
        &f2,
        &fresh(&ctx, &[&a, &b], &now2, ViewMode::Lambert),
    );
    // Nothing is drawn where instance 0 was.
    let left = pixel(-2.5, 0.0);
    assert!(f1.frame.depth[left] > 0.0 && f2.frame.depth[left] == 0.0);

    // Frame 3: an instance added (of a mesh present from the start).
    let added = r
        .scene
        .add_instance(&InstanceDesc {
            mesh: r.scene.mesh_handle(1).expect("mesh"),
            transform: at(-2.0, -1.5, 0.5),
            color: [0.5, 0.5, 0.9],
        })
        .expect("added");
    let f3 = frame(&mut r, ViewMode::Lambert);
    let mut now3 = now2.clone();
    now3.push(place(1, at(-2.0, -1.5, 0.5), [0.5, 0.5, 0.9]));
    assert_same(
        "added",
        &f3,
        &fresh(&ctx, &[&a, &b], &now3, ViewMode::Lambert),
    );
    let slot = r.scene.instance_slot(added).expect("live");
    assert!(
        pixels_of(&f3, slot) > 50,
        "the added instance is visible: {} px",
        pixels_of(&f3, slot)
    );
    assert_no_validation_errors(&ctx);
}

#[test]
fn mesh_added_after_the_first_frame_renders_with_its_materials() {
    let ctx = gpu();
    let a = ball("a", 24, 1.0, [0.9, 0.3, 0.2]);
    let c = ball("c", 20, 0.8, [0.1, 0.8, 0.2]);
    let start = vec![place(0, at(-1.5, 0.0, 0.0), [1.0; 3])];
    let mut r = VgeoRenderer::new(&ctx, &[&a], &start).expect("renderer");
    let lit0 = frame(&mut r, ViewMode::Lit);
    assert_same(
        "lit frame 0",
        &lit0,
        &fresh(&ctx, &[&a], &start, ViewMode::Lit),
    );
    // The added mesh comes from a `.vgeo` file's bytes.
    let c = vgeo::format::load(&vgeo::format::save(&c)).expect("vgeo loads");
    let mc: MeshHandle = r.scene.add_mesh(&c).expect("mesh added");
    assert_eq!(mc.index(), 1);
    r.scene
        .add_instance(&InstanceDesc {
            mesh: mc,
            transform: at(1.6, 0.3, 0.0),
            color: [1.0; 3],
        })
        .expect("instance added");
    let now = vec![start[0], place(1, at(1.6, 0.3, 0.0), [1.0; 3])];
    for mode in [ViewMode::Lit, ViewMode::Lambert, ViewMode::Materials] {
        let f = frame(&mut r, mode);
        assert_same(
            &format!("{mode:?} with the added mesh"),
            &f,
            &fresh(&ctx, &[&a, &c], &now, mode),
        );
    }
    // Its own material: green where the new mesh is, in the lit image.
    let lit = frame(&mut r, ViewMode::Lit);
    let px = pixel(1.6, 0.3);
    let rgb = &lit.frame.color[4 * px..4 * px + 3];
    assert!(
        rgb[1] > rgb[0] + 40 && rgb[1] > rgb[2] + 40,
        "the added mesh shows its green material, got {rgb:?}"
    );
    let concatenated = vgeo::material::SceneMaterials::new(&[&a, &c]).expect("materials");
    let laid_out = r.scene_materials();
    assert_eq!(
        bytemuck::cast_slice::<_, u8>(&laid_out.meshes),
        bytemuck::cast_slice::<_, u8>(&concatenated.meshes),
        "appended in order, the per-mesh table is the concatenation's"
    );
    assert_eq!(laid_out.materials, concatenated.materials);
    assert_no_validation_errors(&ctx);
}

#[test]
fn stale_handles_are_errors() {
    let ctx = gpu();
    let a = ball("a", 12, 1.0, [0.5; 3]);
    let b = ball("b", 12, 0.5, [0.5; 3]);
    let mut r =
        VgeoRenderer::new(&ctx, &[&a], &[place(0, at(0.0, 0.0, 0.0), [1.0; 3])]).expect("renderer");
    let ma = r.scene.mesh_handle(0).expect("mesh");
    let i0 = r.scene.instance_handle(0).expect("instance");
    assert!(matches!(
        r.scene.remove_mesh(ma),
        Err(SceneError::MeshInUse { instances: 1, .. })
    ));
    r.scene.remove_instance(i0).expect("live");
    for e in [
        r.scene.remove_instance(i0),
        r.scene.set_transform(i0, &DMat4::IDENTITY),
        r.scene.set_color(i0, [0.0; 3]),
    ] {
        assert!(
            matches!(e, Err(SceneError::StaleInstance(h)) if h == i0),
            "{e:?}"
        );
    }
    // The handle slot is reused with a new generation: the old handle stays stale.
    let i1 = r
        .scene
        .add_instance(&InstanceDesc {
            mesh: ma,
            transform: DMat4::IDENTITY,
            color: [1.0; 3],
        })
        .expect("added");
    assert_ne!(i0, i1);
    assert!(r.scene.instance_slot(i0).is_err());
    assert_eq!(r.scene.instance_slot(i1).expect("live"), 0);
    r.scene.remove_instance(i1).expect("live");
    r.scene.remove_mesh(ma).expect("unused mesh");
    assert!(matches!(
        r.scene.remove_mesh(ma),
        Err(SceneError::StaleMesh(_))
    ));
    let e = r.scene.add_instance(&InstanceDesc {
        mesh: ma,
        transform: DMat4::IDENTITY,
        color: [1.0; 3],
    });
    assert!(matches!(e, Err(SceneError::StaleMesh(_))), "{e:?}");
    let e = r.scene.add_instances(&[InstanceDesc {
        mesh: ma,
        transform: DMat4::IDENTITY,
        color: [1.0; 3],
    }]);
    assert!(matches!(e, Err(SceneError::StaleMesh(_))));
    // A mesh added into the freed slot gets a handle the old one does not match.
    let mb = r.scene.add_mesh(&b).expect("mesh");
    assert_eq!(mb.index(), ma.index());
    assert_ne!(mb, ma);
    assert!(!r.scene.contains_mesh(ma) && r.scene.contains_mesh(mb));
    // An empty scene renders an empty frame.
    let f = frame(&mut r, ViewMode::Lambert);
    assert_eq!(f.frame.covered(), 0);
    assert_no_validation_errors(&ctx);
}

#[test]
fn buffers_and_capacities_grow_with_the_scene() {
    let ctx = gpu();
    let a = ball("a", 12, 0.3, [0.8, 0.2, 0.2]);
    let b = ball("b", 16, 0.25, [0.2, 0.8, 0.2]);
    let c = ball("c", 20, 0.35, [0.2, 0.2, 0.8]);
    let mut r = VgeoRenderer::new(&ctx, &[&a], &[place(0, at(-3.0, 2.0, 0.0), [1.0; 3])])
        .expect("renderer");
    frame(&mut r, ViewMode::Lambert);
    let mem0 = r.scene.memory();
    let caps0 = r.capacities();
    let inst0 = r.scene.instance_capacity();
    let mb = r.scene.add_mesh(&b).expect("mesh");
    let mut placements = vec![place(0, at(-3.0, 2.0, 0.0), [1.0; 3])];
    let mut handles = vec![r.scene.instance_handle(0).expect("instance")];
    // 40 instances one by one over several frames (each through the staging ring).
    for i in 0..40u32 {
        let (mesh, mi) = if i % 3 == 0 {
            (r.scene.mesh_handle(0).expect("a"), 0)
        } else {
            (mb, 1)
        };
        let t = at(
            -3.0 + (i % 8) as f64 * 0.85,
            1.2 - (i / 8) as f64 * 0.8,
            0.0,
        );
        let color = [0.5 + (i % 5) as f32 * 0.1, 0.6, 0.7];
        handles.push(
            r.scene
                .add_instance(&InstanceDesc {
                    mesh,
                    transform: t,
                    color,
                })
                .expect("added"),
        );
        placements.push(place(mi, t, color));
        if i % 10 == 9 {
            frame(&mut r, ViewMode::Lambert);
        }
    }
    // A third mesh, replacing the removed first instance (mesh a keeps its other instances).
    r.scene.remove_instance(handles[0]).expect("live");
    placements.swap_remove(0);
    handles.swap_remove(0);
    let mc = r.scene.add_mesh(&c).expect("mesh");
    let t = at(2.5, 2.8, 0.0);
    handles.push(
        r.scene
            .add_instance(&InstanceDesc {
                mesh: mc,
                transform: t,
                color: [1.0; 3],
            })
            .expect("added"),
    );
    placements.push(place(2, t, [1.0; 3]));
    // Every instance moves in the same frame, one of them twice (the last write wins).
    for (k, (h, p)) in handles.iter().zip(placements.iter_mut()).enumerate() {
        let t = p.transform * DMat4::from_rotation_y(0.3 + k as f64 * 0.1);
        r.scene.set_transform(*h, &DMat4::IDENTITY).expect("live");
        r.scene.set_transform(*h, &t).expect("live");
        p.transform = t;
    }
    assert_eq!(r.scene.pending_changes(), handles.len());
    let got = frame(&mut r, ViewMode::Lambert);
    assert_eq!(r.scene.pending_changes(), 0);
    // The dense order of the changed scene is the placements' order (swap-remove matched above).
    for (k, h) in handles.iter().enumerate() {
        assert_eq!(r.scene.instance_slot(*h).expect("live"), k as u32);
    }
    assert_same(
        "grown scene",
        &got,
        &fresh(&ctx, &[&a, &b, &c], &placements, ViewMode::Lambert),
    );
    let mem1 = r.scene.memory();
    let caps1 = r.capacities();
    eprintln!("before:\n{mem0}\nafter:\n{mem1}\ncapacities {caps0:?} -> {caps1:?}");
    assert!(r.scene.instance_capacity() >= 41 && r.scene.instance_capacity() > inst0);
    assert!(
        caps1.0 >= caps0.0 && caps1.1 > caps0.1,
        "{caps0:?} -> {caps1:?}"
    );
    assert!(
        caps1.1 as u64 >= r.scene.instance_clusters && r.direct_visible(),
        "the visible list follows the scene: direct slots stay on"
    );
    assert!(mem1.capacity_bytes() > mem0.capacity_bytes());
    assert!(mem1.used_bytes() <= mem1.capacity_bytes());
    let used = |m: &vgeo::scene_gpu::SceneMemory, name: &str| {
        m.buffers
            .iter()
            .find(|b| b.name == name)
            .map(|b| b.used_bytes)
            .expect("buffer listed")
    };
    assert_eq!(used(&mem1, "scene instances"), 96 * 41);
    assert_eq!(
        used(&mem1, "scene cluster locators"),
        8 * (a.clusters.len() + b.clusters.len() + c.clusters.len()) as u64
    );
    // Removing a mesh frees its ranges for the next one: the arenas do not grow.
    let of_c: Vec<InstanceHandle> = handles
        .iter()
        .copied()
        .filter(|h| r.scene.instance(*h).is_ok_and(|i| i.mesh == mc.index()))
        .collect();
    assert_eq!(of_c.len(), 1);
    for h in of_c {
        r.scene.remove_instance(h).expect("live");
    }
    r.scene.remove_mesh(mc).expect("unused");
    let before = r.scene.geometry_bytes();
    let mc2 = r.scene.add_mesh(&c).expect("mesh");
    assert_eq!(
        r.scene.geometry_bytes(),
        before,
        "the freed ranges are reused"
    );
    assert_eq!(mc2.index(), mc.index());
    assert_no_validation_errors(&ctx);
}

#[test]
fn transform_updates_do_not_allocate_once_warm() {
    let ctx = gpu();
    let a = ball("a", 12, 0.2, [0.8; 3]);
    let placements: Vec<Placement> = (0..200)
        .map(|i| {
            place(
                0,
                at(
                    (i % 20) as f64 * 0.4 - 4.0,
                    (i / 20) as f64 * 0.4 - 2.0,
                    0.0,
                ),
                [1.0; 3],
            )
        })
        .collect();
    let mut r = VgeoRenderer::new(&ctx, &[&a], &placements).expect("renderer");
    let handles: Vec<InstanceHandle> = (0..200)
        .map(|i| r.scene.instance_handle(i).expect("handle"))
        .collect();
    let step = |r: &mut VgeoRenderer, frame: u32| {
        // 50 scattered instances move (every fourth), one of them twice.
        for (k, h) in handles
            .iter()
            .enumerate()
            .filter(|(k, _)| k % 4 == frame as usize % 4)
        {
            let t = at(k as f64 * 0.01, frame as f64 * 0.01, 0.0);
            r.scene.set_transform(*h, &t).expect("live");
        }
        r.scene
            .set_transform(handles[frame as usize % 4], &DMat4::IDENTITY)
            .expect("live");
        r.scene.prepare_updates().expect("staged");
        r.scene.updates_submitted();
    };
    // Warm-up: the dirty list, the regions and both ring buffers reach their size.
    for f in 0..4 {
        step(&mut r, f);
    }
    for f in 4..8 {
        let n = allocations(|| step(&mut r, f));
        assert_eq!(
            n, 0,
            "frame {f}: {n} heap allocations for 50 transform updates"
        );
    }
    // The counter works: a frame's first growth allocates.
    for h in &handles {
        r.scene.set_transform(*h, &DMat4::IDENTITY).expect("live");
    }
    let n = allocations(|| r.scene.prepare_updates().expect("staged"));
    assert!(n > 0, "growing the ring to 200 instances allocates");
    r.scene.updates_submitted();
    let f = frame(&mut r, ViewMode::Lambert);
    assert!(f.frame.covered() > 0);
    assert_no_validation_errors(&ctx);
}
