//! vgeo's `stress` scene rendered headless by Bevy's virtual geometry (meshlets), GPU time per
//! frame of vgeo's camera path. See README.md.

mod mesh_io;
mod scene;
mod timing;

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicI64, Ordering};
use std::time::{Duration, Instant};

use bevy::{
    app::{AppExit, ScheduleRunnerPlugin},
    asset::RenderAssetUsages,
    camera::RenderTarget,
    core_pipeline::tonemapping::Tonemapping,
    mesh::{Indices, PrimitiveTopology},
    pbr::experimental::meshlet::{
        MESHLET_DEFAULT_VERTEX_POSITION_QUANTIZATION_FACTOR, MeshletMesh, MeshletMesh3d,
        MeshletPlugin,
    },
    prelude::*,
    render::{
        RenderPlugin,
        pipelined_rendering::PipelinedRenderingPlugin,
        render_resource::{TextureFormat, TextureUsages},
        settings::{Backends, RenderCreation, WgpuSettings},
        view::screenshot::{Screenshot, ScreenshotCaptured},
    },
    window::ExitCondition,
};

use scene::StressScene;
use timing::{FrameTimes, TimingPlugin};

pub const BEVY_VERSION: &str = "0.19.1";

#[derive(Clone, Debug)]
pub struct Args {
    pub n: u32,
    pub mesh: PathBuf,
    pub width: u32,
    pub height: u32,
    pub frames: u32,
    pub warmup_passes: u32,
    pub settle_frames: u32,
    pub plain: bool,
    pub build_only: bool,
    pub passes: bool,
    pub out: Option<PathBuf>,
    pub png: Option<PathBuf>,
    pub png_frame: Option<u32>,
    pub cluster_slots: u32,
    pub timeout_s: u64,
}

const USAGE: &str = "\
usage: vgeo-peer-bevy --n N [options]
  --n N               grid size: N x N x N instances (1..=100)
  --mesh PATH         the stress scene's mesh (default ../../../shared/assets/scanned/turbineblade.ply,
                      as in assets/scenes/stress.toml, relative to the current directory)
  --width W --height H  render target size (default 1920 x 1080, as vgeo's full suite)
  --frames F          frames of the camera path (default 16, as vgeo's full suite)
  --warmup-passes K   untimed passes over the path before the timed one (default 1)
  --settle-frames S   untimed frames at the first camera before the warm-up (default 8)
  --plain             ordinary meshes (Mesh3d), no meshlets: for GPUs without 64-bit image atomics
  --build-only        only build the MeshletMesh (CPU; no GPU needed), print its time and exit
  --passes            also report Bevy's per-pass GPU times (RenderDiagnosticsPlugin: timestamps in
                      every pass, so off by default), means over the timed pass
  --out FILE          write the JSON report there (default: stdout only)
  --png FILE          save the image of one timed frame (--png-frame, default (frames - 1) / 2:
                      the frame whose image vgeo bench saves) as PNG
  --cluster-slots C   MeshletPlugin::cluster_buffer_slots (default 2^25, Bevy's maximum)
  --timeout S         give up (exit 124) after S seconds (default 900)";

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        n: 0,
        mesh: PathBuf::from("../../../shared/assets/scanned/turbineblade.ply"),
        width: 1920,
        height: 1080,
        frames: 16,
        warmup_passes: 1,
        settle_frames: 8,
        plain: false,
        build_only: false,
        passes: false,
        out: None,
        png: None,
        png_frame: None,
        cluster_slots: 1 << 25,
        timeout_s: 900,
    };
    let mut it = std::env::args().skip(1);
    while let Some(k) = it.next() {
        if k == "--plain" {
            a.plain = true;
            continue;
        }
        if k == "--passes" {
            a.passes = true;
            continue;
        }
        if k == "--build-only" {
            a.build_only = true;
            continue;
        }
        if k == "-h" || k == "--help" {
            println!("{USAGE}");
            std::process::exit(0);
        }
        let v = it.next().ok_or(format!("{k} needs a value"))?;
        let num = |v: &str| v.parse::<u64>().map_err(|_| format!("{k}: bad number {v}"));
        match k.as_str() {
            "--n" | "--stress-n" => a.n = num(&v)? as u32,
            "--mesh" => a.mesh = v.into(),
            "--width" => a.width = num(&v)? as u32,
            "--height" => a.height = num(&v)? as u32,
            "--frames" => a.frames = num(&v)? as u32,
            "--warmup-passes" => a.warmup_passes = num(&v)? as u32,
            "--settle-frames" => a.settle_frames = num(&v)? as u32,
            "--out" => a.out = Some(v.into()),
            "--png" => a.png = Some(v.into()),
            "--png-frame" => a.png_frame = Some(num(&v)? as u32),
            "--cluster-slots" => a.cluster_slots = num(&v)? as u32,
            "--timeout" => a.timeout_s = num(&v)?,
            _ => return Err(format!("unknown argument {k}\n{USAGE}")),
        }
    }
    if !(1..=100).contains(&a.n) {
        return Err(format!("--n must be 1..=100 (got {})\n{USAGE}", a.n));
    }
    if a.frames == 0 || a.width == 0 || a.height == 0 {
        return Err("--frames, --width and --height must be positive".into());
    }
    if a.cluster_slots == 0 || a.cluster_slots > 1 << 25 {
        return Err("--cluster-slots must be 1..=2^25".into());
    }
    Ok(a)
}

fn fail(code: i32, msg: &str) -> ! {
    eprintln!("vgeo-peer-bevy: error: {msg}");
    std::process::exit(code);
}

fn main() {
    let args = parse_args().unwrap_or_else(|e| fail(2, &e));
    // A clear one-line failure instead of a backtrace, and a watchdog instead of a hang.
    std::panic::set_hook(Box::new(|info| {
        let msg = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_default();
        let at = info
            .location()
            .map(|l| format!(" ({}:{})", l.file(), l.line()))
            .unwrap_or_default();
        eprintln!("vgeo-peer-bevy: error: panic: {msg}{at}");
        std::process::exit(101);
    }));
    let timeout = args.timeout_s;
    std::thread::spawn(move || {
        std::thread::sleep(Duration::from_secs(timeout));
        eprintln!("vgeo-peer-bevy: error: timed out after {timeout} s");
        std::process::exit(124);
    });

    let t0 = Instant::now();
    let mesh = mesh_io::load(&args.mesh).unwrap_or_else(|e| fail(2, &e));
    let load_s = t0.elapsed().as_secs_f64();
    let scene = StressScene::new(&mesh, &args);
    eprintln!(
        "vgeo-peer-bevy: {} ({} vertices, {} triangles) loaded in {load_s:.2} s; N = {}: {} instances, {} scene triangles",
        args.mesh.display(),
        mesh.positions.len(),
        mesh.indices.len() / 3,
        args.n,
        scene.placements.len(),
        scene.placements.len() as u64 * (mesh.indices.len() / 3) as u64
    );

    let adapter = if args.build_only {
        String::new()
    } else {
        let a = timing::check_adapter(!args.plain).unwrap_or_else(|e| fail(3, &e));
        eprintln!("vgeo-peer-bevy: adapter {a}");
        a
    };

    let bevy_mesh = to_bevy_mesh(&mesh);
    let mut meshlet_build_s = 0.0;
    let meshlet = if args.plain {
        None
    } else {
        // from_mesh runs on Bevy's async compute pool (made here before the App's TaskPoolPlugin,
        // which keeps it): all cores.
        bevy::tasks::AsyncComputeTaskPool::get_or_init(|| {
            bevy::tasks::TaskPoolBuilder::new()
                .thread_name("meshlet build".into())
                .build()
        });
        let t = Instant::now();
        let m = MeshletMesh::from_mesh(
            &bevy_mesh,
            MESHLET_DEFAULT_VERTEX_POSITION_QUANTIZATION_FACTOR,
        )
        .unwrap_or_else(|e| fail(3, &format!("MeshletMesh::from_mesh: {e}")));
        meshlet_build_s = t.elapsed().as_secs_f64();
        eprintln!("vgeo-peer-bevy: MeshletMesh built in {meshlet_build_s:.2} s");
        Some(m)
    };
    if args.build_only {
        return;
    }

    let shared = Arc::new(Shared::default());
    let mut app = App::new();
    let mut plugins = DefaultPlugins
        .set(WindowPlugin {
            primary_window: None,
            exit_condition: ExitCondition::DontExit,
            ..default()
        })
        .set(RenderPlugin {
            render_creation: RenderCreation::Automatic(Box::new(WgpuSettings {
                backends: Some(Backends::VULKAN),
                ..default()
            })),
            // Pipelines compile when first used (blocking), so no warm-up frame lacks a draw.
            synchronous_pipeline_compilation: true,
            ..default()
        })
        .set(bevy::log::LogPlugin {
            filter: "warn,bevy_pbr::meshlet=info,wgpu=error,naga=warn".into(),
            ..default()
        })
        // One frame's CPU and GPU work in order: the timestamps of frame i are read in frame i.
        .disable::<PipelinedRenderingPlugin>();
    if cfg!(debug_assertions) {
        plugins = plugins.set(bevy::log::LogPlugin::default());
    }
    app.add_plugins(plugins)
        .add_plugins(ScheduleRunnerPlugin::run_loop(Duration::ZERO))
        .add_plugins(TimingPlugin(shared.clone()));
    if args.passes {
        app.add_plugins(bevy::render::diagnostic::RenderDiagnosticsPlugin);
    }
    if !args.plain {
        app.add_plugins(MeshletPlugin {
            cluster_buffer_slots: args.cluster_slots,
        });
    }
    app.insert_resource(ClearColor(Color::linear_rgb(0.02, 0.02, 0.03)))
        .insert_resource(Bench {
            args: args.clone(),
            scene,
            mesh: Some(bevy_mesh),
            meshlet,
            adapter,
            target: None,
            camera: None,
            frame: 0,
            started: None,
            setup_s: 0.0,
            load_s,
            meshlet_build_s,
            wall_ms: Vec::new(),
            last: None,
            png_pending: false,
            done_frames: 0,
            shared: shared.clone(),
        })
        .add_systems(Startup, setup)
        .add_systems(Update, drive);
    let exit = app.run();
    match exit {
        AppExit::Success => {}
        AppExit::Error(c) => std::process::exit(c.get() as i32),
    }
}

/// Shared by the main world and the render world (no pipelining: the main world's update runs
/// before the render world's frame).
#[derive(Default)]
pub struct Shared {
    /// The timed frame the render world draws now (-1: an untimed frame).
    pub tag: AtomicI64,
    pub times: std::sync::Mutex<FrameTimes>,
    pub png_saved: AtomicBool,
    /// Fraction of the saved image's pixels that differ from the clear colour (f64 bits; a
    /// sanity check that the scene was drawn at all).
    pub png_coverage: std::sync::atomic::AtomicU64,
}

#[derive(Resource)]
struct Bench {
    args: Args,
    scene: StressScene,
    mesh: Option<Mesh>,
    meshlet: Option<MeshletMesh>,
    adapter: String,
    target: Option<Handle<Image>>,
    camera: Option<Entity>,
    frame: u32,
    started: Option<Instant>,
    setup_s: f64,
    load_s: f64,
    meshlet_build_s: f64,
    wall_ms: Vec<f64>,
    last: Option<Instant>,
    png_pending: bool,
    done_frames: u32,
    shared: Arc<Shared>,
}

fn to_bevy_mesh(m: &mesh_io::TriMesh) -> Mesh {
    let uvs = vec![[0f32, 0f32]; m.positions.len()];
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::MAIN_WORLD | RenderAssetUsages::RENDER_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, m.positions.clone())
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, m.normals())
    .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, uvs)
    .with_inserted_indices(Indices::U32(m.indices.clone()))
}

fn setup(
    mut commands: Commands,
    mut bench: ResMut<Bench>,
    mut images: ResMut<Assets<Image>>,
    mut meshes: ResMut<Assets<Mesh>>,
    meshlets: Option<ResMut<Assets<MeshletMesh>>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let t = Instant::now();
    let (w, h) = (bench.args.width, bench.args.height);
    let mut image = Image::new_target_texture(w, h, TextureFormat::Rgba8UnormSrgb, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = images.add(image);
    bench.target = Some(target.clone());

    let c = bench.scene.color;
    let material = materials.add(StandardMaterial {
        base_color: Color::linear_rgb(c[0], c[1], c[2]),
        perceptual_roughness: 0.8,
        ..default()
    });
    let placements = bench.scene.placements.clone();
    if let (Some(m), Some(mut meshlets)) = (bench.meshlet.take(), meshlets) {
        let handle = meshlets.add(m);
        commands.spawn_batch(placements.into_iter().map(move |tf| {
            (
                MeshletMesh3d(handle.clone()),
                MeshMaterial3d(material.clone()),
                tf,
            )
        }));
    } else {
        let handle = meshes.add(bench.mesh.take().expect("mesh"));
        commands.spawn_batch(
            placements
                .into_iter()
                .map(move |tf| (Mesh3d(handle.clone()), MeshMaterial3d(material.clone()), tf)),
        );
    }

    let d = bench.scene.light_dir;
    commands.spawn((
        DirectionalLight {
            illuminance: 3_000.0,
            shadow_maps_enabled: false,
            ..default()
        },
        Transform::from_translation(d).looking_at(Vec3::ZERO, Vec3::Y),
    ));

    let cam = &bench.scene.cameras[0];
    let camera = commands
        .spawn((
            Camera3d::default(),
            RenderTarget::Image(target.into()),
            Tonemapping::None,
            Msaa::Off,
            Projection::Perspective(PerspectiveProjection {
                fov: bench.scene.fov_y,
                near: bench.scene.near,
                far: bench.scene.far,
                ..default()
            }),
            Transform::from_translation(cam.0).looking_at(cam.1, Vec3::Y),
        ))
        .id();
    bench.camera = Some(camera);
    bench.setup_s = t.elapsed().as_secs_f64();
}

/// Settle frames at the first camera, `warmup_passes` untimed passes over the path, one timed pass,
/// then a few frames to collect the last timestamps and the PNG.
fn drive(
    mut commands: Commands,
    mut bench: ResMut<Bench>,
    mut cameras: Query<&mut Transform, With<Camera3d>>,
    mut exit: MessageWriter<AppExit>,
    mut store: ResMut<bevy::diagnostic::DiagnosticsStore>,
) {
    let now = Instant::now();
    if bench.started.is_none() {
        bench.started = Some(now);
    }
    let frames = bench.args.frames;
    let settle = bench.args.settle_frames;
    let untimed = settle + bench.args.warmup_passes * frames;
    let f = bench.frame;
    bench.frame += 1;
    if let Some(last) = bench.last
        && f > untimed
        && f <= untimed + frames
    {
        bench.wall_ms.push((now - last).as_secs_f64() * 1e3);
    }
    bench.last = Some(now);

    let Some(camera) = bench.camera else { return };
    let Ok(mut tf) = cameras.get_mut(camera) else {
        return;
    };
    let (index, tag) = if f < settle {
        (0, -1)
    } else if f < untimed {
        ((f - settle) % frames, -1)
    } else if f < untimed + frames {
        (f - untimed, (f - untimed) as i64)
    } else {
        (frames - 1, -1)
    };
    let (eye, target) = bench.scene.cameras[index as usize];
    *tf = Transform::from_translation(eye).looking_at(target, Vec3::Y);
    bench.shared.tag.store(tag, Ordering::SeqCst);
    if f == settle {
        eprintln!(
            "vgeo-peer-bevy: first {settle} frames in {:.2} s; warm-up",
            (now - bench.started.unwrap()).as_secs_f64()
        );
    }

    let png_frame = bench.args.png_frame.unwrap_or((frames - 1) / 2);
    if tag >= 0 && tag as u32 == png_frame && bench.args.png.is_some() {
        let path = bench.args.png.clone().unwrap();
        let shared = bench.shared.clone();
        bench.png_pending = true;
        commands
            .spawn(Screenshot::image(bench.target.clone().unwrap()))
            .observe(move |ev: On<ScreenshotCaptured>| {
                match save_png(&path, &ev.image) {
                    Ok(()) => eprintln!("vgeo-peer-bevy: saved {}", path.display()),
                    Err(e) => eprintln!("vgeo-peer-bevy: error: PNG {}: {e}", path.display()),
                }
                shared
                    .png_coverage
                    .store(coverage(&ev.image).to_bits(), Ordering::SeqCst);
                shared.png_saved.store(true, Ordering::SeqCst);
            });
    }

    if f == untimed {
        for d in store.iter_mut() {
            d.clear_history();
        }
    }
    if f >= untimed + frames {
        bench.done_frames += 1;
        let have_all = bench.shared.times.lock().unwrap().complete(frames);
        let png_ok = !bench.png_pending || bench.shared.png_saved.load(Ordering::SeqCst);
        if (have_all && png_ok) || bench.done_frames > 30 {
            let mut passes = Vec::new();
            for d in store.iter() {
                let path = d.path().as_str();
                if let Some(name) = path
                    .strip_prefix("render/")
                    .and_then(|p| p.strip_suffix("/elapsed_gpu"))
                {
                    let v: Vec<f64> = d.values().copied().collect();
                    if !v.is_empty() {
                        passes.push((
                            name.to_string(),
                            v.iter().sum::<f64>() / v.len() as f64,
                            v.len(),
                        ));
                    }
                }
            }
            passes.sort_by(|a, b| b.1.total_cmp(&a.1));
            let code = report(&bench, &passes);
            exit.write(if code == 0 {
                AppExit::Success
            } else {
                AppExit::from_code(code)
            });
        }
    }
}

/// Fraction of pixels away from the clear colour: linear (0.02, 0.02, 0.03) is sRGB (39, 39, 48).
fn coverage(image: &Image) -> f64 {
    let Some(data) = image.data.as_ref() else {
        return f64::NAN;
    };
    let px = data.chunks_exact(4);
    let n = px.len().max(1);
    let drawn = px
        .filter(|p| {
            (p[0] as i32 - 39).abs() > 3
                || (p[1] as i32 - 39).abs() > 3
                || (p[2] as i32 - 48).abs() > 3
        })
        .count();
    drawn as f64 / n as f64
}

fn save_png(path: &std::path::Path, image: &Image) -> Result<(), String> {
    let (w, h) = (image.width(), image.height());
    let data = image.data.as_ref().ok_or("no image data")?;
    if data.len() < (w * h * 4) as usize {
        return Err(format!("image data {} bytes for {w}x{h}", data.len()));
    }
    let file = std::fs::File::create(path).map_err(|e| e.to_string())?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut wr = enc.write_header().map_err(|e| e.to_string())?;
    // Opaque: the clear colour and the surfaces are; the target's alpha need not be.
    let mut rgba = data[..(w * h * 4) as usize].to_vec();
    for px in rgba.chunks_exact_mut(4) {
        px[3] = 255;
    }
    wr.write_image_data(&rgba).map_err(|e| e.to_string())
}

fn stats(v: &[f64]) -> String {
    if v.is_empty() {
        return "null".into();
    }
    let mut s = v.to_vec();
    s.sort_by(|a, b| a.total_cmp(b));
    let mean = s.iter().sum::<f64>() / s.len() as f64;
    let median = if s.len() % 2 == 1 {
        s[s.len() / 2]
    } else {
        0.5 * (s[s.len() / 2 - 1] + s[s.len() / 2])
    };
    format!(
        "{{\"mean\": {mean:.4}, \"median\": {median:.4}, \"min\": {:.4}, \"max\": {:.4}}}",
        s[0],
        s[s.len() - 1]
    )
}

fn list(v: &[Option<f64>]) -> String {
    let items: Vec<String> = v
        .iter()
        .map(|x| x.map_or("null".into(), |x| format!("{x:.4}")))
        .collect();
    format!("[{}]", items.join(", "))
}

fn pass_list(passes: &[(String, f64, usize)]) -> String {
    if passes.is_empty() {
        return "null".into();
    }
    let items: Vec<String> = passes
        .iter()
        .map(|(n, ms, k)| {
            format!(
                "{{\"pass\": {}, \"ms\": {ms:.4}, \"samples\": {k}}}",
                json_str(n)
            )
        })
        .collect();
    format!("[\n    {}\n  ]", items.join(",\n    "))
}

fn json_str(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// Writes the JSON report (stdout and --out) and a markdown line; returns the exit code.
fn report(bench: &Bench, passes: &[(String, f64, usize)]) -> u8 {
    let a = &bench.args;
    let times = bench.shared.times.lock().unwrap();
    let gpu: Vec<Option<f64>> = (0..a.frames).map(|i| times.gpu_ms(i)).collect();
    let got: Vec<f64> = gpu.iter().flatten().copied().collect();
    let wall: Vec<Option<f64>> = bench.wall_ms.iter().map(|&x| Some(x)).collect();
    let tris = bench.scene.mesh_triangles;
    let inst = bench.scene.placements.len() as u64;
    let s = &bench.scene;
    let missing = a.frames as usize - got.len();
    let mode = if a.plain { "plain" } else { "meshlet" };
    let json = format!(
        "{{\n  \"peer\": \"bevy\",\n  \"bevy_version\": \"{BEVY_VERSION}\",\n  \"mode\": \"{mode}\",\n  \"adapter\": {},\n  \"timestamps\": {},\n  \"stress_n\": {},\n  \"instances\": {inst},\n  \"mesh\": {},\n  \"mesh_triangles\": {tris},\n  \"scene_triangles\": {},\n  \"width\": {},\n  \"height\": {},\n  \"frames\": {},\n  \"warmup_passes\": {},\n  \"settle_frames\": {},\n  \"cluster_buffer_slots\": {},\n  \"spacing\": {:.6},\n  \"near\": {:.6},\n  \"fov_y_deg\": 45.0,\n  \"load_s\": {:.3},\n  \"meshlet_build_s\": {:.3},\n  \"spawn_s\": {:.3},\n  \"gpu_ms\": {},\n  \"gpu_ms_stats\": {},\n  \"frame_wall_ms\": {},\n  \"frame_wall_ms_stats\": {},\n  \"missing_gpu_frames\": {missing},\n  \"png_frame\": {},\n  \"png_coverage\": {},\n  \"passes_gpu_ms_mean\": {}\n}}\n",
        json_str(&bench.adapter),
        times.supported,
        a.n,
        json_str(&a.mesh.display().to_string()),
        inst * tris,
        a.width,
        a.height,
        a.frames,
        a.warmup_passes,
        a.settle_frames,
        if a.plain { 0 } else { a.cluster_slots },
        s.spacing,
        s.near,
        bench.load_s,
        bench.meshlet_build_s,
        bench.setup_s,
        list(&gpu),
        stats(&got),
        list(&wall),
        stats(&bench.wall_ms),
        if bench.png_pending {
            a.png_frame.unwrap_or((a.frames - 1) / 2).to_string()
        } else {
            "null".into()
        },
        if bench.png_pending && bench.shared.png_saved.load(Ordering::SeqCst) {
            format!(
                "{:.4}",
                f64::from_bits(bench.shared.png_coverage.load(Ordering::SeqCst))
            )
        } else {
            "null".into()
        },
        pass_list(passes),
    );
    print!("{json}");
    if let Some(out) = &a.out
        && let Err(e) = std::fs::write(out, &json)
    {
        eprintln!("vgeo-peer-bevy: error: cannot write {}: {e}", out.display());
        return 1;
    }
    let med = |v: &[f64]| {
        let mut s = v.to_vec();
        s.sort_by(|a, b| a.total_cmp(b));
        if s.is_empty() {
            f64::NAN
        } else {
            s[s.len() / 2]
        }
    };
    eprintln!(
        "| bevy {BEVY_VERSION} {mode} | N={} | {} instances | {:.3e} tris | GPU ms median {:.3} (min {:.3}, max {:.3}) | wall ms median {:.1} |",
        a.n,
        inst,
        (inst * tris) as f64,
        med(&got),
        got.iter().copied().fold(f64::INFINITY, f64::min),
        got.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        med(&bench.wall_ms)
    );
    if times.supported && missing > 0 {
        eprintln!("vgeo-peer-bevy: error: {missing} timed frames have no GPU time");
        return 4;
    }
    0
}
