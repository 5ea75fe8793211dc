//! vgeo recording into a host's frame (issue 12 items 2, 3, 5, 7). The example's host
//! (examples/embed.rs, included here) runs on lavapipe with validation and synchronization
//! validation: its image equals `vgeo render` of the same scene and camera, its depth image holds
//! vgeo's depth, the host's triangles and vgeo's geometry occlude each other by depth, and two
//! views recorded into one command buffer each equal a single-view render.

mod common;

#[allow(dead_code)]
#[path = "../examples/embed.rs"]
mod example;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use common::{assert_no_validation_errors, assets, gpu};
use vgeo::camera::Camera;
use vgeo::frame::{HostTargets, VgeoRenderer, ViewFrame};
use vgeo::gpu::{Image, RenderTarget, vk};
use vgeo::imgerr::psnr_rgb;
use vgeo::material::ShadeMode;
use vgeo::passes::debug_view::ViewMode;
use vgeo::passes::view::FrameSettings;
use vgeo::render::{Light, Placement};

/// Counts heap allocations of the current thread while `COUNTING` is on (recording must make none).
struct CountingAlloc;

thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

// SAFETY: forwards to the system allocator; the counters are thread-local `Cell`s with const
// initializers (no allocation of their own).
unsafe impl GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.with(|c| c.get()) {
            ALLOCATIONS.with(|a| a.set(a.get() + 1));
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
            ALLOCATIONS.with(|a| a.set(a.get() + 1));
        }
        // SAFETY: as for `alloc` and `dealloc`.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOC: CountingAlloc = CountingAlloc;

/// Heap allocations `f` makes on this thread.
fn allocations<R>(f: impl FnOnce() -> R) -> (R, u64) {
    ALLOCATIONS.with(|a| a.set(0));
    COUNTING.with(|c| c.set(true));
    let r = f();
    COUNTING.with(|c| c.set(false));
    (r, ALLOCATIONS.with(|a| a.get()))
}

/// The example's host at a test size: spot and a cube, 300 instances, 8 frames with 2 in flight.
fn options(host_draws: bool, vgeo_draws: bool) -> example::Options {
    example::Options {
        frames: 8,
        frames_in_flight: 2,
        instances: 300,
        width: 160,
        height: 96,
        meshes: vec![
            assets().join("spot.obj").to_string_lossy().into_owned(),
            "generated:box".into(),
        ],
        host_draws,
        vgeo_draws,
        validate: true,
        out: None,
        geometry_budget: None,
        still_from: None,
        orbit: 1.0,
    }
}

fn run(host_draws: bool, vgeo_draws: bool) -> example::Output {
    let out = example::run(&options(host_draws, vgeo_draws)).expect("the host runs");
    assert!(
        out.validation_errors.is_empty(),
        "{} validation error(s) (synchronization validation: {}):\n{}",
        out.validation_errors.len(),
        out.sync_validation,
        out.validation_errors.join("\n")
    );
    out
}

/// vgeo's own `render` of the example's scene and last camera: (colour, depth).
fn reference(out: &example::Output) -> (Vec<u8>, Vec<f32>) {
    let ctx = gpu();
    let mut r = VgeoRenderer::new(&ctx, &out.built, &out.placements).unwrap();
    let f = r
        .render(
            &out.camera,
            out.width,
            out.height,
            &FrameSettings::default(),
            ViewMode::Lit,
            &Light::default(),
        )
        .unwrap();
    f.check().unwrap();
    assert_no_validation_errors(&ctx);
    (f.frame.color, f.frame.depth)
}

#[test]
fn the_hosts_image_equals_vgeo_render_where_the_host_draws_nothing() {
    let out = run(false, true);
    eprintln!(
        "synchronization validation: {}; stats of {} frames, last {} triangles",
        out.sync_validation, out.stats_frames, out.last_triangles
    );
    // Every frame's stats came back, without waiting (the last ones after the final fence).
    assert_eq!(out.stats_frames, 8);
    assert!(out.last_triangles > 1000);
    let (color, depth) = reference(&out);
    let psnr = psnr_rgb(&out.color, &color);
    eprintln!("embedded vs render: {psnr:.1} dB");
    assert!(psnr >= 45.0, "embedded frame vs vgeo render: {psnr:.1} dB");
    // The host's depth image holds vgeo's depth (reverse-Z, 0 where empty), bit for bit.
    let covered = depth.iter().filter(|d| **d > 0.0).count();
    assert!(covered > out.depth.len() / 4, "the grid fills the view");
    let same = out
        .depth
        .iter()
        .zip(&depth)
        .filter(|(a, b)| a.to_bits() == b.to_bits())
        .count();
    assert_eq!(
        same,
        depth.len(),
        "exported depth equals the visibility buffer's"
    );
}

/// Issue 13 item 4: streaming inside a host's frame loop with 2 frames in flight. The host steps
/// the streamer after each fence wait; the step reads the page feedback the finished frames left
/// in host memory and stages its loads and evictions for the next frame's `update_scene`, without
/// submitting or waiting. Under three quarters of the scene's page bytes, once the camera stops,
/// the image settles to the one with every page resident, bit for bit. (Eviction under a tight
/// budget is tests/streaming.rs's.)
#[test]
fn a_streamed_scene_in_the_hosts_frames_settles_to_the_all_resident_image() {
    let mut opts = options(false, true);
    opts.meshes = vec![
        assets().join("bunny.ply").to_string_lossy().into_owned(),
        assets().join("spot.obj").to_string_lossy().into_owned(),
    ];
    // Close to a few instances while the camera moves over 12 frames, so that the view wants
    // detail beyond the always-resident pages.
    opts.instances = 12;
    opts.orbit = 0.3;
    (opts.width, opts.height) = (320, 192);
    opts.frames = 40;
    opts.still_from = Some(12);
    let built = example::build_meshes(&opts.meshes).expect("meshes build");
    let pages: u64 = built
        .iter()
        .flat_map(|m| m.pages.iter().map(|p| p.bytes as u64))
        .sum();
    let resident_prefix: u64 = built
        .iter()
        .flat_map(|m| {
            m.pages[..m.resident_pages as usize]
                .iter()
                .map(|p| p.bytes as u64)
        })
        .sum();
    assert!(
        pages > 4 * resident_prefix,
        "most pages stream: {pages} B of pages, {resident_prefix} B always resident"
    );
    let streamed = {
        let mut o = opts.clone();
        o.geometry_budget = Some(pages * 3 / 4);
        example::run(&o).expect("the streamed host runs")
    };
    assert!(
        streamed.validation_errors.is_empty(),
        "{} validation error(s):\n{}",
        streamed.validation_errors.len(),
        streamed.validation_errors.join("\n")
    );
    let st = streamed.stream.clone().expect("streaming summary");
    eprintln!("{st:?}, pages {pages} B, always resident {resident_prefix} B");
    assert_eq!(st.waits, 0, "a streaming step waited for the GPU");
    assert!(st.uploads > 0, "pages were streamed in");
    assert!(st.peak_resident_bytes <= pages * 3 / 4, "{st:?}");
    assert!(
        st.last_requests == 0 && st.last_settled,
        "settled: nothing asked, staged or read any more"
    );
    // The same scene, every page resident.
    let full = example::run(&opts).expect("the all-resident host runs");
    assert!(full.validation_errors.is_empty());
    assert_eq!(streamed.camera.position, full.camera.position);
    let same_depth = streamed
        .depth
        .iter()
        .zip(&full.depth)
        .all(|(a, b)| a.to_bits() == b.to_bits());
    assert!(
        same_depth,
        "settled depth differs from the all-resident one"
    );
    assert_eq!(streamed.color, full.color, "settled colour differs");
}

#[test]
fn the_hosts_triangles_and_vgeo_occlude_each_other() {
    let both = run(true, true);
    let vgeo_only = run(false, true);
    let host_only = run(true, false);
    let tris = example::host_triangles();
    let colour_of = |c: [f32; 4]| c.map(|x| (x * 255.0).round() as u8);
    let (red, blue) = (colour_of(tris[0].1), colour_of(tris[1].1));
    let px = |img: &[u8], i: usize| [img[4 * i], img[4 * i + 1], img[4 * i + 2], img[4 * i + 3]];
    // Per host triangle (drawn before vgeo / after vgeo): pixels where it is nearer, where vgeo is.
    let mut host_nearer = [0usize; 2];
    let mut vgeo_nearer = [0usize; 2];
    let mut wrong = Vec::new();
    for i in 0..both.depth.len() {
        let (dh, dv) = (host_only.depth[i], vgeo_only.depth[i]);
        let hc = px(&host_only.color, i);
        let which = if hc == red {
            0
        } else if hc == blue {
            1
        } else {
            // No host triangle here: the frame is vgeo's.
            if px(&both.color, i) != px(&vgeo_only.color, i) {
                wrong.push((i, "outside the host's triangles"));
            }
            continue;
        };
        if dh > dv * 1.001 {
            host_nearer[which] += 1;
            if px(&both.color, i) != hc || both.depth[i] != dh {
                wrong.push((i, "host nearer, not shown"));
            }
        } else if dv > dh * 1.001 {
            vgeo_nearer[which] += 1;
            if px(&both.color, i) != px(&vgeo_only.color, i) || both.depth[i] != dv {
                wrong.push((i, "vgeo nearer, not shown"));
            }
        }
    }
    eprintln!("host nearer {host_nearer:?}, vgeo nearer {vgeo_nearer:?}");
    for k in 0..2 {
        assert!(
            host_nearer[k] > 50,
            "triangle {k} in front of vgeo somewhere"
        );
        assert!(vgeo_nearer[k] > 50, "triangle {k} behind vgeo somewhere");
    }
    assert!(
        wrong.is_empty(),
        "{} pixels wrong, e.g. {:?}",
        wrong.len(),
        &wrong[..wrong.len().min(10)]
    );
}

/// A cleared colour (vgeo's background) and depth (0) target pair, as a host would hand them in.
fn targets(ctx: &vgeo::gpu::Context, w: u32, h: u32) -> (Image, Image) {
    let color = Image::new(
        ctx,
        "test colour",
        w,
        h,
        vgeo::frame::HOST_COLOR_FORMAT,
        vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::TRANSFER_SRC,
    )
    .unwrap();
    let depth = Image::new(
        ctx,
        "test depth",
        w,
        h,
        vgeo::frame::HOST_DEPTH_FORMAT,
        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
            | vk::ImageUsageFlags::TRANSFER_SRC
            | vk::ImageUsageFlags::TRANSFER_DST,
    )
    .unwrap();
    (color, depth)
}

/// The host's own pass before vgeo's frame: colour cleared to vgeo's background, depth to 0 (far).
fn host_clear(cmd: &mut vgeo::gpu::Cmd, color: &Image, depth: &Image) {
    let bg = vgeo::render::BACKGROUND.map(|c| c.clamp(0.0, 1.0).powf(1.0 / 2.2));
    cmd.begin_rendering(
        &[RenderTarget {
            image: color,
            clear: Some(bg),
        }],
        Some(RenderTarget {
            image: depth,
            clear: Some([0.0; 4]),
        }),
    );
    cmd.end_rendering();
}

/// A lit frame of `camera` into the host's `color` and `depth`.
fn lit_frame<'a>(frame: u64, camera: &'a Camera, color: &Image, depth: &Image) -> ViewFrame<'a> {
    ViewFrame {
        frame,
        camera,
        settings: FrameSettings::default(),
        light: Light::default(),
        shade: ShadeMode::Lit,
        targets: HostTargets {
            depth: Some(depth.as_host()),
            color: Some(color.as_host()),
            gbuffer: None,
        },
    }
}

#[test]
fn two_views_in_one_frame_each_equal_a_single_view_render() {
    let ctx = gpu();
    let built = example::build_meshes(&[
        assets().join("spot.obj").to_string_lossy().into_owned(),
        "generated:box".into(),
    ])
    .unwrap();
    let placements: Vec<Placement> = example::placements(&built, 200);
    let mut r = VgeoRenderer::new(&ctx, &built, &placements).unwrap();
    let sizes = [(128u32, 96u32), (96, 80)];
    let cameras: [Camera; 2] = [example::camera_at(0), example::camera_at(150)];
    let mut views = [
        r.create_view("main", sizes[0].0, sizes[0].1, 2).unwrap(),
        r.create_view("second", sizes[1].0, sizes[1].1, 2).unwrap(),
    ];
    let imgs = [
        targets(&ctx, sizes[0].0, sizes[0].1),
        targets(&ctx, sizes[1].0, sizes[1].1),
    ];
    // Three frames, both views in each, one submission per frame. Recording allocates nothing on
    // the heap.
    let mut recorded_allocations = Vec::new();
    for frame in 0..3u64 {
        ctx.submit_and_wait("two views", |cmd| {
            for (k, view) in views.iter_mut().enumerate() {
                let (color, depth) = &imgs[k];
                host_clear(cmd, color, depth);
                let f = lit_frame(frame, &cameras[k], color, depth);
                let (res, n) = allocations(|| r.record_cmd(cmd, view, &f));
                res.unwrap();
                recorded_allocations.push(n);
            }
        })
        .unwrap();
        for view in &views {
            let s = view
                .try_stats(frame)
                .unwrap()
                .expect("stats after the wait");
            s.check().unwrap();
            assert!(s.triangles() > 100);
        }
    }
    assert_no_validation_errors(&ctx);
    eprintln!("heap allocations per recorded view-frame: {recorded_allocations:?}");
    assert!(
        recorded_allocations.iter().all(|n| *n == 0),
        "recording allocated: {recorded_allocations:?}"
    );
    // The allocation counter works (it would catch an allocation in the recording).
    assert!(allocations(|| vec![1u8; 3]).1 >= 1);
    // Frame 0's slot has been recorded again by frame 2 (2 frames in flight): its stats are gone.
    assert!(views[0].try_stats(0).unwrap().is_none());
    assert!(views[0].try_stats(2).unwrap().is_some());
    for k in 0..2 {
        let (w, h) = sizes[k];
        let got = imgs[k].0.download().unwrap();
        let mut single = VgeoRenderer::new(&ctx, &built, &placements).unwrap();
        let f = single
            .render(
                &cameras[k],
                w,
                h,
                &FrameSettings::default(),
                ViewMode::Lit,
                &Light::default(),
            )
            .unwrap();
        let psnr = psnr_rgb(&got, &f.frame.color);
        eprintln!("view {k}: {psnr:.1} dB against a single-view render");
        assert!(psnr >= 45.0, "view {k}: {psnr:.1} dB");
        assert!(f.frame.covered() > (w * h / 4) as usize);
    }
    // The views differ (different cameras), so neither result is the other's.
    assert_ne!(
        imgs[0].0.download().unwrap().len(),
        imgs[1].0.download().unwrap().len()
    );
    assert_no_validation_errors(&ctx);
}

#[test]
fn the_gbuffer_into_the_hosts_targets_equals_vgeos_own() {
    let ctx = gpu();
    let built = example::build_meshes(&[
        assets().join("spot.obj").to_string_lossy().into_owned(),
        "generated:box".into(),
    ])
    .unwrap();
    let placements = example::placements(&built, 100);
    let (w, h) = (112u32, 80u32);
    let camera = example::camera_at(40);
    let mut r = VgeoRenderer::new(&ctx, &built, &placements).unwrap();
    let mut view = r.create_view("gbuffer", w, h, 2).unwrap();
    let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
        | vk::ImageUsageFlags::STORAGE
        | vk::ImageUsageFlags::TRANSFER_SRC;
    let names = ["host albedo", "host normal", "host params"];
    let gb: Vec<Image> = vgeo::frame::HOST_GBUFFER_FORMATS
        .iter()
        .zip(names)
        .map(|(f, n)| Image::new(&ctx, n, w, h, *f, usage).unwrap())
        .collect();
    let (_, depth) = targets(&ctx, w, h);
    ctx.submit_and_wait("host gbuffer", |cmd| {
        // The host's GBuffer cleared to a marker the host's own pixels would carry.
        let clear = Some([0.0, 0.0, 0.0, 0.0]);
        cmd.begin_rendering(
            &[
                RenderTarget {
                    image: &gb[0],
                    clear,
                },
                RenderTarget {
                    image: &gb[1],
                    clear,
                },
                RenderTarget {
                    image: &gb[2],
                    clear,
                },
            ],
            Some(RenderTarget {
                image: &depth,
                clear: Some([0.0; 4]),
            }),
        );
        cmd.end_rendering();
        let f = ViewFrame {
            frame: 0,
            camera: &camera,
            settings: FrameSettings::default(),
            light: Light::default(),
            shade: ShadeMode::Lit,
            targets: HostTargets {
                depth: Some(depth.as_host()),
                color: None,
                gbuffer: Some([gb[0].as_host(), gb[1].as_host(), gb[2].as_host()]),
            },
        };
        r.record_cmd(cmd, &mut view, &f).unwrap();
    })
    .unwrap();
    assert_no_validation_errors(&ctx);
    // vgeo's own frame: its GBuffer, valid where covered (vgeo's own GBuffer is not cleared:
    // coverage is material_classify's per-pixel material).
    let mut single = VgeoRenderer::new(&ctx, &built, &placements).unwrap();
    single
        .render(
            &camera,
            w,
            h,
            &FrameSettings::default(),
            ViewMode::Lit,
            &Light::default(),
        )
        .unwrap();
    let passes = single.material_passes().unwrap();
    let own = &passes.targets().unwrap().gbuffer;
    let pixel_materials = passes.pixel_materials().unwrap();
    let covered: Vec<usize> = (0..(w * h) as usize)
        .filter(|&i| pixel_materials[i] != u32::MAX)
        .collect();
    // The host's GBuffer (cleared by the host) is written exactly where vgeo covers.
    let host_albedo = gb[0].download().unwrap();
    for i in 0..(w * h) as usize {
        let alpha = host_albedo[4 * i + 3];
        assert_eq!(
            alpha > 127,
            pixel_materials[i] != u32::MAX,
            "host albedo alpha {alpha} at pixel {i}"
        );
    }
    assert!(
        covered.len() > (w * h / 4) as usize,
        "{} covered",
        covered.len()
    );
    for (k, (own_img, texel)) in [(&own.albedo, 4usize), (&own.normal, 8), (&own.params, 4)]
        .into_iter()
        .enumerate()
    {
        let a = own_img.download().unwrap();
        let b = gb[k].download().unwrap();
        for &i in &covered {
            assert_eq!(
                a[texel * i..texel * (i + 1)],
                b[texel * i..texel * (i + 1)],
                "{} at pixel {i}",
                names[k]
            );
        }
        // Where vgeo draws nothing, the host's GBuffer keeps what the host put there.
        let untouched = (0..(w * h) as usize)
            .filter(|&i| pixel_materials[i] == u32::MAX)
            .all(|i| b[texel * i..texel * (i + 1)].iter().all(|x| *x == 0));
        assert!(untouched, "{}: uncovered pixels untouched", names[k]);
    }
    assert_no_validation_errors(&ctx);
}

/// A steady-state frame of a host, everything vgeo does on the CPU per frame (every instance's
/// transform changed, the scene update staged and recorded, the view recorded), allocates nothing
/// on the heap once warm; the moved instances are drawn where they went.
#[test]
fn a_steady_state_frame_with_moving_instances_allocates_nothing() {
    let ctx = gpu();
    let built = example::build_meshes(&[
        assets().join("spot.obj").to_string_lossy().into_owned(),
        "generated:box".into(),
    ])
    .unwrap();
    let placements: Vec<Placement> = example::placements(&built, 200);
    let mut r = VgeoRenderer::new(&ctx, &built, &placements).unwrap();
    let (w, h) = (96u32, 64u32);
    let mut view = r.create_view("main", w, h, 2).unwrap();
    let (color, depth) = targets(&ctx, w, h);
    let handles: Vec<_> = (0..placements.len() as u32)
        .map(|j| r.scene.instance_handle(j).unwrap())
        .collect();
    let camera = example::camera_at(0);
    let mut per_frame = Vec::new();
    let frames = 6u32;
    for i in 0..frames {
        ctx.submit_and_wait("steady state", |cmd| {
            host_clear(cmd, &color, &depth);
            let f = lit_frame(i as u64, &camera, &color, &depth);
            let (res, n) = allocations(|| -> vgeo::gpu::GpuResult<()> {
                for (j, (&hd, p)) in handles.iter().zip(&placements).enumerate() {
                    r.scene
                        .set_transform(hd, &example::transform_at(p, j as u32, i))
                        .map_err(vgeo::gpu::GpuError::from)?;
                }
                r.update_scene_cmd(cmd, &mut [&mut view])?;
                r.record_cmd(cmd, &mut view, &f)
            });
            res.unwrap();
            per_frame.push(n);
        })
        .unwrap();
    }
    assert_no_validation_errors(&ctx);
    eprintln!(
        "heap allocations per frame (set_transform x200, update_scene, record): {per_frame:?}"
    );
    // The first frames grow the staging ring; from then on nothing.
    assert!(
        per_frame[2..].iter().all(|n| *n == 0),
        "steady-state frames allocated: {per_frame:?}"
    );
    // The last frame shows the last frame's places.
    let moved: Vec<Placement> = placements
        .iter()
        .enumerate()
        .map(|(j, p)| Placement {
            transform: example::transform_at(p, j as u32, frames - 1),
            ..*p
        })
        .collect();
    let mut fresh = VgeoRenderer::new(&ctx, &built, &moved).unwrap();
    let want = fresh
        .render(
            &camera,
            w,
            h,
            &FrameSettings::default(),
            ViewMode::Lit,
            &Light::default(),
        )
        .unwrap();
    let psnr = psnr_rgb(&color.download().unwrap(), &want.frame.color);
    assert!(
        psnr >= 45.0,
        "{psnr:.1} dB against a fresh render of the last places"
    );
}

/// The automatic SW/HW split of a host's frames: each view's tuner is fed the times of its own
/// frames as their slots come round again (no wait, no allocation), and settles on a threshold of
/// the ladder.
#[test]
fn a_views_automatic_split_settles_from_its_own_frames() {
    let ctx = gpu();
    let built =
        example::build_meshes(&[assets().join("spot.obj").to_string_lossy().into_owned()]).unwrap();
    let placements: Vec<Placement> = example::placements(&built, 20);
    let mut r = VgeoRenderer::new(&ctx, &built, &placements).unwrap();
    let (w, h) = (96u32, 64u32);
    let mut view = r.create_view("main", w, h, 2).unwrap();
    let (color, depth) = targets(&ctx, w, h);
    let camera = example::camera_at(0);
    assert_eq!(view.hw_split(), (64.0, false), "a new view starts at 64");
    let mut frames = 0u64;
    let mut per_frame = Vec::new();
    while !view.hw_split().1 && frames < 2000 {
        ctx.submit_and_wait("split", |cmd| {
            host_clear(cmd, &color, &depth);
            let f = lit_frame(frames, &camera, &color, &depth);
            let (res, n) = allocations(|| -> vgeo::gpu::GpuResult<()> {
                r.update_scene_cmd(cmd, &mut [&mut view])?;
                r.record_cmd(cmd, &mut view, &f)
            });
            res.unwrap();
            per_frame.push(n);
        })
        .unwrap();
        frames += 1;
        if frames == 4
            && view
                .try_stats(2)
                .unwrap()
                .is_some_and(|s| s.gpu_ms.is_empty())
        {
            eprintln!("no timestamps: the split stays at 64");
            assert_eq!(view.hw_split(), (64.0, false));
            return;
        }
    }
    let (chosen, settled) = view.hw_split();
    eprintln!("settled on {chosen} px after {frames} frames");
    assert!(settled, "not settled after {frames} frames");
    // Measuring, deciding and switching happen inside `record`, which allocates nothing once
    // warm (the first frames grow the staging ring).
    assert!(
        per_frame[2..].iter().all(|n| *n == 0),
        "frames allocated while the split was tuned: {per_frame:?}"
    );
    assert!(vgeo::frame::split::SPLIT_LADDER.contains(&chosen));
    assert_no_validation_errors(&ctx);
}
