//! The material passes on lavapipe with validation on: per-material draws shade exactly their
//! pixels (fragment counters against the CPU's count from the visibility buffer), tile ranges,
//! FlightHelmet's shaded image against a CPU-shaded reference (PSNR), meshes without UVs or normals,
//! 1,024 materials, and an unreadable texture.

mod common;

use common::{assert_no_validation_errors, assets, gpu, shared_assets};
use glam::{DMat4, DVec3, Mat4, Vec2, Vec3, Vec4};
use vgeo::baseline::brute::Brute;
use vgeo::baseline::lod::{Lod, LodOptions};
use vgeo::builder::quantize::{decode_normal, decode_uv};
use vgeo::builder::{BuildOptions, BuiltMesh, build};
use vgeo::camera::Camera;
use vgeo::frame::{VgeoFrame, VgeoRenderer};
use vgeo::material::{MESH_HAS_UVS, SceneMaterials, TextureData, srgb_to_linear};
use vgeo::mesh::{Material, Mesh};
use vgeo::passes::debug_view::ViewMode;
use vgeo::passes::emit_gbuffer::EmitPath;
use vgeo::passes::material_classify::{MATERIAL_TILE, NO_MATERIAL};
use vgeo::passes::view::FrameSettings;
use vgeo::render::{Light, Placement};

fn exact() -> FrameSettings {
    FrameSettings {
        error_px: 0.0,
        ..FrameSettings::default()
    }
}

fn white_placement() -> Vec<Placement> {
    vec![Placement {
        mesh: 0,
        transform: DMat4::IDENTITY,
        color: [1.0; 3],
    }]
}

/// A `cols` x `rows` grid of cells over x in [-w/2, w/2], y in [-h/2, h/2] (z = 0, facing +z), each
/// cell `sub` x `sub` quads of material `cell index % materials.len()`.
fn grid_mesh(cols: u32, rows: u32, sub: u32, size: [f32; 2], materials: Vec<Material>) -> Mesh {
    grid_mesh_uv(cols, rows, sub, size, materials, false)
}

/// [`grid_mesh`], with UVs (u along +x, v along -y, over the whole grid) if `uvs`.
fn grid_mesh_uv(
    cols: u32,
    rows: u32,
    sub: u32,
    size: [f32; 2],
    materials: Vec<Material>,
    uvs: bool,
) -> Mesh {
    let mut m = Mesh {
        name: "grid".into(),
        materials,
        has_normals: false,
        has_uvs: uvs,
        ..Default::default()
    };
    let n = cols * sub;
    let k = rows * sub;
    for cy in 0..rows {
        for cx in 0..cols {
            let mat = (cy * cols + cx) % m.materials.len() as u32;
            let base = m.positions.len() as u32;
            for j in 0..=sub {
                for i in 0..=sub {
                    let gx = (cx * sub + i) as f32 / n as f32;
                    let gy = (cy * sub + j) as f32 / k as f32;
                    m.positions
                        .push([(gx - 0.5) * size[0], (0.5 - gy) * size[1], 0.0]);
                    m.normals.push([0.0, 0.0, 1.0]);
                    m.uvs.push([gx, gy]);
                }
            }
            let row = sub + 1;
            for j in 0..sub {
                for i in 0..sub {
                    let a = base + j * row + i;
                    let (b, c, d) = (a + 1, a + row, a + row + 1);
                    m.indices.extend_from_slice(&[a, c, b, b, c, d]);
                    m.material_ids.extend_from_slice(&[mat, mat]);
                }
            }
        }
    }
    m.validate().expect("grid mesh is valid");
    m
}

fn front_camera(dist: f64) -> Camera {
    Camera::look_at(
        DVec3::new(0.0, 0.0, dist),
        DVec3::ZERO,
        Vec3::Y,
        45f32.to_radians(),
        0.05,
    )
}

/// The global material of mesh `mesh`'s vertex `v`: the mesh's first global id plus the vertex's
/// local material (clamped to the mesh's last), as `material_classify` computes it.
fn global_material(mats: &SceneMaterials, built: &BuiltMesh, mesh: usize, v: u32) -> u32 {
    let mm = &mats.meshes[mesh];
    let local = built.vertex_materials.get(v as usize).copied().unwrap_or(0) as u32;
    mm.material_offset + local.min(mm.material_count.max(1) - 1)
}

/// Per pixel, the global material of its triangle's first vertex from the visibility buffer (CPU
/// decode), `NO_MATERIAL` where empty.
fn cpu_pixel_materials(
    f: &VgeoFrame,
    built: &[BuiltMesh],
    placements: &[Placement],
    mats: &SceneMaterials,
) -> Vec<u32> {
    // First cluster of each mesh in the scene's concatenation.
    let mut first = vec![0u32];
    for b in built {
        let c = *first.last().unwrap();
        first.push(c + b.clusters.len() as u32);
    }
    f.visbuffer
        .iter()
        .map(|&v| {
            if v == 0 {
                return NO_MATERIAL;
            }
            let lo = v as u32;
            let ([instance, cluster], _) =
                f.resolve(v).expect("a drawn pixel names a visible cluster");
            let mesh = placements[instance as usize].mesh as usize;
            let c0 = first[mesh];
            let tri = built[mesh].cluster_triangles((cluster - c0) as usize)[(lo & 127) as usize];
            global_material(mats, &built[mesh], mesh, tri[0])
        })
        .collect()
}

#[test]
fn each_material_draw_shades_only_its_pixels() {
    for path in [EmitPath::Compute, EmitPath::Raster] {
        each_material_draw_shades_only_its_pixels_with(path);
    }
}

fn each_material_draw_shades_only_its_pixels_with(path: EmitPath) {
    eprintln!("emit_gbuffer {path:?}");
    const W: u32 = 320;
    const H: u32 = 160;
    let ctx = gpu();
    let colours = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 0.0],
        [1.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.5, 0.25, 0.1],
    ];
    let materials: Vec<Material> = colours
        .iter()
        .enumerate()
        .map(|(i, c)| Material {
            name: format!("m{i}"),
            base_color: [c[0], c[1], c[2], 1.0],
            ..Material::default()
        })
        .collect();
    let mesh = grid_mesh(4, 2, 4, [4.0, 2.0], materials);
    let built = build(&mesh, &BuildOptions::default()).expect("grid builds");
    let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &white_placement())
        .expect("renderer");
    r.set_count_fragments(true);
    r.set_emit_path(path);
    let camera = front_camera(2.6);
    let f = r
        .render(&camera, W, H, &exact(), ViewMode::Albedo, &Light::default())
        .expect("albedo frame");
    f.check().expect("complete frame");
    let mats = r.scene_materials().clone();
    let cpu = cpu_pixel_materials(&f, std::slice::from_ref(&built), &white_placement(), &mats);
    let passes = r.material_passes().expect("material passes exist");
    assert_eq!(passes.pixel_materials().expect("pixel ids"), cpu);

    // Fragments per material draw == pixels of that material.
    let counts = passes.fragment_counts().expect("counts");
    let mut expected = vec![0u32; 8];
    for &m in cpu.iter().filter(|&&m| m != NO_MATERIAL) {
        expected[m as usize] += 1;
    }
    eprintln!("fragments per material: {counts:?} (CPU pixels: {expected:?})");
    assert_eq!(counts, expected);
    assert!(
        expected.iter().all(|&c| c > 500),
        "every region is on screen"
    );
    let empty = cpu.iter().filter(|&&m| m == NO_MATERIAL).count();
    assert!(empty > 0, "some background");

    // Tile ranges are exactly the CPU's, and they prune: each material touches only some tiles.
    let tiles = passes.tile_ranges().expect("tiles");
    let tx = W.div_ceil(MATERIAL_TILE);
    let ty = H.div_ceil(MATERIAL_TILE);
    let mut cpu_tiles = vec![[NO_MATERIAL, 0u32]; (tx * ty) as usize];
    for (i, &m) in cpu.iter().enumerate() {
        if m == NO_MATERIAL {
            continue;
        }
        let (x, y) = (i as u32 % W, i as u32 / W);
        let t = &mut cpu_tiles[((y / MATERIAL_TILE) * tx + x / MATERIAL_TILE) as usize];
        t[0] = t[0].min(m);
        t[1] = t[1].max(m);
    }
    assert_eq!(tiles, cpu_tiles);
    let drawn: Vec<usize> = (0..8u32)
        .map(|m| tiles.iter().filter(|t| t[0] <= m && m <= t[1]).count())
        .collect();
    eprintln!("tiles drawn per material (of {}): {drawn:?}", tiles.len());
    assert!(drawn.iter().all(|&d| d < tiles.len()));

    // The albedo view shows each pixel's own material colour.
    for (i, &m) in cpu.iter().enumerate() {
        let px = &f.frame.color[4 * i..4 * i + 3];
        let want: Vec<u8> = if m == NO_MATERIAL {
            continue;
        } else {
            colours[m as usize]
                .iter()
                .map(|c| (c.powf(1.0 / 2.2) * 255.0).round() as u8)
                .collect()
        };
        for k in 0..3 {
            assert!(
                (px[k] as i32 - want[k] as i32).abs() <= 1,
                "pixel {i}: {px:?} vs material {m}'s {want:?}"
            );
        }
    }
    assert_no_validation_errors(&ctx);
}

#[test]
fn material_ids_are_offset_per_mesh() {
    const W: u32 = 192;
    const H: u32 = 192;
    let mat = |i: u32| Material {
        name: format!("m{i}"),
        base_color: [0.2 + 0.2 * i as f32, 0.5, 1.0 - 0.2 * i as f32, 1.0],
        ..Material::default()
    };
    let a = grid_mesh(2, 1, 2, [2.0, 0.8], (0..2).map(mat).collect());
    let b = grid_mesh(3, 1, 2, [2.0, 0.8], (2..5).map(mat).collect());
    let built: Vec<BuiltMesh> = [&a, &b]
        .iter()
        .map(|m| build(m, &BuildOptions::default()).expect("grid builds"))
        .collect();
    let at = |mesh: u32, y: f64, x: f64| Placement {
        mesh,
        transform: DMat4::from_translation(DVec3::new(x, y, 0.0)),
        color: [1.0; 3],
    };
    // Mesh 1 first among the instances, and mesh 0 twice: ids follow meshes, not instances.
    let placements = vec![at(1, -0.5, 0.0), at(0, 0.5, -0.6), at(0, 0.5, 0.6)];
    let ctx = gpu();
    let mut r = VgeoRenderer::new(&ctx, &built, &placements).expect("renderer");
    assert_eq!(r.scene_materials().count(), 5);
    r.set_count_fragments(true);
    let f = r
        .render(
            &front_camera(3.0),
            W,
            H,
            &exact(),
            ViewMode::Materials,
            &Light::default(),
        )
        .expect("frame");
    f.check().expect("complete frame");
    let mats = r.scene_materials().clone();
    let cpu = cpu_pixel_materials(&f, &built, &placements, &mats);
    let passes = r.material_passes().expect("material passes");
    assert_eq!(passes.pixel_materials().expect("ids"), cpu);
    let mut expected = vec![0u32; 5];
    for &m in cpu.iter().filter(|&&m| m != NO_MATERIAL) {
        expected[m as usize] += 1;
    }
    let counts = passes.fragment_counts().expect("counts");
    eprintln!("two meshes: fragments per material {counts:?}");
    assert_eq!(counts, expected);
    assert!(
        expected.iter().all(|&c| c > 100),
        "all five materials on screen"
    );
    assert_no_validation_errors(&ctx);
}

#[test]
fn normal_maps_follow_the_gltf_tangent_convention() {
    const W: u32 = 192;
    const H: u32 = 96;
    let dir = std::env::temp_dir().join(format!("vgeo-normal-maps-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let map = |name: &str, rgb: [u8; 3]| {
        let path = dir.join(name);
        let img = image::RgbaImage::from_pixel(4, 4, image::Rgba([rgb[0], rgb[1], rgb[2], 255]));
        img.save(&path).expect("write normal map");
        path
    };
    let towards_u = map("u.png", [255, 128, 128]);
    let up = map("up.png", [128, 255, 128]);
    let materials: Vec<Material> = [Some(towards_u), Some(up), None]
        .into_iter()
        .enumerate()
        .map(|(i, normal_texture)| Material {
            name: format!("m{i}"),
            normal_texture,
            ..Material::default()
        })
        .collect();
    let mesh = grid_mesh_uv(3, 1, 2, [3.0, 1.0], materials, true);
    let built = build(&mesh, &BuildOptions::default()).expect("grid builds");
    let ctx = gpu();
    let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &white_placement())
        .expect("renderer");
    let f = r
        .render(
            &front_camera(2.0),
            W,
            H,
            &exact(),
            ViewMode::Normals,
            &Light::default(),
        )
        .expect("frame");
    f.check().expect("complete frame");
    let mats = r.scene_materials().clone();
    let cpu = cpu_pixel_materials(&f, std::slice::from_ref(&built), &white_placement(), &mats);
    // World normals: +x (u grows to the right), +y (glTF: green is up, v grows downwards), +z,
    // everywhere (a perturbed normal leaning away from the view ray is not flipped).
    let want = [[255u8, 128, 128], [128, 255, 128], [128, 128, 255]];
    let mut seen = [0usize; 3];
    for (i, &m) in cpu.iter().enumerate() {
        if m == NO_MATERIAL {
            continue;
        }
        let px = &f.frame.color[4 * i..4 * i + 3];
        for k in 0..3 {
            assert!(
                (px[k] as i32 - want[m as usize][k] as i32).abs() <= 3,
                "pixel {i} of material {m}: normal colour {px:?}, expected {:?}",
                want[m as usize]
            );
        }
        seen[m as usize] += 1;
    }
    eprintln!("normal-mapped pixels per material: {seen:?}");
    assert!(seen.iter().all(|&n| n > 100));
    let _ = std::fs::remove_dir_all(&dir);
    assert_no_validation_errors(&ctx);
}

/// A texture's levels (level 0 first) as the GPU has them.
struct Mips {
    levels: Vec<(u32, u32, Vec<u8>)>,
}

impl Mips {
    fn new(t: &TextureData) -> Self {
        let mut levels = vec![(t.width, t.height, t.rgba.clone())];
        levels.extend(t.mip_chain());
        Self { levels }
    }

    /// Bilinear, repeat, one level, sRGB decoded per texel (what an `_SRGB` format's sampler does).
    fn bilinear(&self, level: usize, uv: Vec2) -> Vec4 {
        let (tw, th, rgba) = &self.levels[level];
        let (w, h) = (*tw as i64, *th as i64);
        let x = uv.x * *tw as f32 - 0.5;
        let y = uv.y * *th as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let texel = |i: i64, j: i64| {
            let i = i.rem_euclid(w) as usize;
            let j = j.rem_euclid(h) as usize;
            let p = &rgba[4 * (j * *tw as usize + i)..][..4];
            Vec4::new(
                srgb_to_linear(p[0]),
                srgb_to_linear(p[1]),
                srgb_to_linear(p[2]),
                p[3] as f32 / 255.0,
            )
        };
        let (i, j) = (x0 as i64, y0 as i64);
        let top = texel(i, j) * (1.0 - fx) + texel(i + 1, j) * fx;
        let bottom = texel(i, j + 1) * (1.0 - fx) + texel(i + 1, j + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// Trilinear `textureGrad`: level of detail log2 of the longer scaled derivative.
    fn sample_grad(&self, uv: Vec2, ddx: Vec2, ddy: Vec2) -> Vec4 {
        let size = Vec2::new(self.levels[0].0 as f32, self.levels[0].1 as f32);
        let rho = (ddx * size).length().max((ddy * size).length());
        let max_level = (self.levels.len() - 1) as f32;
        let lod = rho.log2().clamp(0.0, max_level);
        if !lod.is_finite() || lod <= 0.0 {
            return self.bilinear(0, uv);
        }
        let l0 = lod.floor();
        let f = lod - l0;
        let a = self.bilinear(l0 as usize, uv);
        if f == 0.0 {
            return a;
        }
        a * (1.0 - f) + self.bilinear(l0 as usize + 1, uv) * f
    }
}

fn ray_barycentrics(dir: Vec3, p: &[Vec3; 3]) -> Option<Vec2> {
    let e1 = p[1] - p[0];
    let e2 = p[2] - p[0];
    let pv = dir.cross(e2);
    let det = e1.dot(pv);
    if det.abs() <= 1e-30 {
        return None;
    }
    let tv = -p[0];
    Some(Vec2::new(tv.dot(pv), dir.dot(tv.cross(e1))) / det)
}

fn q8(x: f32) -> f32 {
    (x.clamp(0.0, 1.0) * 255.0).round() / 255.0
}

/// CPU shading of one pixel as emit_gbuffer + shade do it (identity transform, one mesh).
#[allow(clippy::too_many_arguments)]
fn cpu_shade(
    built: &BuiltMesh,
    mats: &SceneMaterials,
    textures: &[Mips],
    level0_only: bool,
    camera: &Camera,
    inv: &Mat4,
    light: Vec3,
    tint: Vec3,
    tri: [u32; 3],
    x: u32,
    y: u32,
    w: u32,
    h: u32,
) -> [u8; 3] {
    let ray = |px: Vec2| {
        let ndc = px / Vec2::new(w as f32, h as f32) * 2.0 - 1.0;
        let a = *inv * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        a.truncate() / a.w
    };
    let cam = camera.position;
    let p = tri.map(|v| {
        let o = built.position(v);
        (DVec3::new(o[0] as f64, o[1] as f64, o[2] as f64) - cam).as_vec3()
    });
    let n = tri.map(|v| {
        Vec3::from(decode_normal(
            built.vertices[v as usize].normal,
            built.quantization.normal_bits,
        ))
    });
    let uv = tri.map(|v| {
        Vec2::from(decode_uv(
            &built.quantization,
            built.vertices[v as usize].uv,
        ))
    });
    let mat = mats.materials[global_material(mats, built, 0, tri[0]) as usize];
    let dir = ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
    let face = (p[1] - p[0]).cross(p[2] - p[0]);
    let mut albedo = Vec4::from(mat.base_color) * tint.extend(1.0);
    let mut normal = face;
    if let Some(b) = ray_barycentrics(dir, &p) {
        let bx = b.x.clamp(0.0, 1.0);
        let by = b.y.clamp(0.0, 1.0).min(1.0 - bx);
        normal = n[0] * (1.0 - bx - by) + n[1] * bx + n[2] * by;
        if mats.meshes[0].flags & MESH_HAS_UVS != 0 {
            let t = uv[0] * (1.0 - b.x - b.y) + uv[1] * b.x + uv[2] * b.y;
            let pc = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let bx = ray_barycentrics(ray(pc + Vec2::X), &p).unwrap_or(b);
            let by = ray_barycentrics(ray(pc + Vec2::Y), &p).unwrap_or(b);
            let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
            let ddx = d1 * (bx.x - b.x) + d2 * (bx.y - b.y);
            let ddy = d1 * (by.x - b.x) + d2 * (by.y - b.y);
            let tex = &textures[mat.base_color_texture as usize];
            albedo *= if level0_only {
                tex.bilinear(0, t)
            } else {
                tex.sample_grad(t, ddx, ddy)
            };
        }
    }
    if normal.length_squared() <= 0.0 {
        normal = face;
    }
    let mut normal = normal.normalize();
    if normal.dot(dir) > 0.0 {
        normal = -normal;
    }
    let albedo = albedo
        .truncate()
        .map(|c| q8(c.clamp(0.0, 1.0).powf(1.0 / 2.2)).powf(2.2));
    let metallic = q8(mat.metallic);
    let roughness = q8(mat.roughness);
    let v = -dir.normalize();
    let hv = (light + v).normalize();
    let r4 = roughness.powi(4);
    let s = 2.0 / r4.max(1e-4) - 2.0;
    let blinn = normal.dot(hv).max(0.0).powf(s) * (s + 8.0) / (8.0 * std::f32::consts::PI) * 0.25;
    let f0 = Vec3::splat(0.04).lerp(albedo, metallic);
    let ndl = normal.dot(light);
    let lit = albedo * (1.0 - metallic) * (0.2 + 0.8 * ndl.abs())
        + f0 * (0.2 + 0.8 * ndl.max(0.0) * blinn);
    lit.to_array()
        .map(|c| (c.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0).round() as u8)
}

#[test]
fn flight_helmet_shaded_matches_cpu_reference() {
    let compute = flight_helmet_shaded_with(EmitPath::Compute);
    let raster = flight_helmet_shaded_with(EmitPath::Raster);
    let p = psnr(&compute, &raster);
    eprintln!("emit_gbuffer compute vs raster: PSNR {p:.2} dB");
    assert!(p >= 60.0, "the two emit_gbuffer forms differ: {p:.2} dB");
}

/// FlightHelmet lit through `path` against the CPU re-shade (>= 40 dB); returns the image.
fn flight_helmet_shaded_with(emit: EmitPath) -> Vec<u8> {
    const W: u32 = 256;
    const H: u32 = 256;
    let path = shared_assets().join("gltf/FlightHelmet/FlightHelmet.gltf");
    let (mesh, report) = vgeo::mesh::load_mesh(&path).expect("FlightHelmet loads");
    assert!(
        report.warnings.iter().any(|w| w.contains("not found")),
        "the asset lacks some textures and the importer says so"
    );
    let built = build(&mesh, &BuildOptions::default()).expect("FlightHelmet builds");
    let ctx = gpu();
    let tint = [1.0, 0.95, 0.9];
    let placements = vec![Placement {
        mesh: 0,
        transform: DMat4::IDENTITY,
        color: tint,
    }];
    let mut r =
        VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &placements).expect("renderer");
    r.set_emit_path(emit);
    let (lo, hi) = mesh.bounds().expect("bounds");
    let camera = Camera::frame_bounds(
        DVec3::from(lo.map(f64::from)),
        DVec3::from(hi.map(f64::from)),
        W as f32 / H as f32,
    );
    let light = Light::default();
    let f = r
        .render(&camera, W, H, &exact(), ViewMode::Lit, &light)
        .expect("shaded frame");
    f.check().expect("complete frame");
    let mats = r.scene_materials().clone();
    assert!(mats.texture_paths.len() >= 4, "base-colour textures found");
    let (textures, warnings) = mats.load_textures();
    assert!(warnings.is_empty(), "{warnings:?}");
    let textures: Vec<Mips> = textures.iter().map(Mips::new).collect();
    let inv = camera.view_proj(W, H).inverse();
    let (mut se, mut covered, mut worst) = (0.0f64, 0usize, 0i32);
    // Against a reference without mip mapping: the GPU image must be farther from it.
    let mut se_level0 = 0.0f64;
    for (i, &v) in f.visbuffer.iter().enumerate() {
        let got = &f.frame.color[4 * i..4 * i + 3];
        if v == 0 {
            continue;
        }
        let lo = v as u32;
        let (entry, _) = f.resolve(v).expect("a drawn pixel names a visible cluster");
        let tri = built.cluster_triangles(entry[1] as usize)[(lo & 127) as usize];
        let shade = |level0_only| {
            cpu_shade(
                &built,
                &mats,
                &textures,
                level0_only,
                &camera,
                &inv,
                light.direction.normalize(),
                Vec3::from(tint),
                tri,
                i as u32 % W,
                i as u32 / W,
                W,
                H,
            )
        };
        let want = shade(false);
        let want0 = shade(true);
        for k in 0..3 {
            let d0 = got[k] as f64 - want0[k] as f64;
            se_level0 += d0 * d0;
            let d = got[k] as i32 - want[k] as i32;
            se += (d * d) as f64;
            worst = worst.max(d.abs());
        }
        covered += 1;
    }
    assert!(covered > (W * H / 8) as usize, "the helmet covers the view");
    let mse = se / (3 * covered) as f64;
    let psnr = 10.0 * (255.0f64 * 255.0 / mse.max(1e-12)).log10();
    let psnr0 = 10.0 * (255.0f64 * 255.0 * (3 * covered) as f64 / se_level0.max(1e-12)).log10();
    eprintln!(
        "{emit:?}: FlightHelmet shaded vs CPU reference: PSNR {psnr:.2} dB over {covered} covered pixels (max channel diff {worst}); vs a reference without mip mapping: {psnr0:.2} dB"
    );
    assert!(psnr0 < psnr - 3.0, "the GPU samples the mip chain");
    if let Ok(dir) = std::env::var("VGEO_TEST_DUMP") {
        f.frame
            .save_png(&std::path::Path::new(&dir).join("material_flight_helmet.png"))
            .expect("dump");
    }
    assert!(psnr >= 40.0, "PSNR {psnr:.2} dB < 40 dB");
    assert_no_validation_errors(&ctx);
    f.frame.color
}

#[test]
fn thousand_materials_without_uvs_or_normals_and_a_bad_texture() {
    const W: u32 = 256;
    const H: u32 = 256;
    let dir = std::env::temp_dir().join(format!("vgeo-material-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let bad = dir.join("not_an_image.png");
    std::fs::write(&bad, b"this is not a PNG").expect("write bad texture");
    let materials: Vec<Material> = (0..1024u32)
        .map(|i| Material {
            name: format!("m{i}"),
            base_color: [
                (i % 8) as f32 / 7.0,
                ((i / 8) % 8) as f32 / 7.0,
                (i / 64) as f32 / 15.0,
                1.0,
            ],
            metallic: (i % 3) as f32 * 0.5,
            roughness: 0.2 + (i % 5) as f32 * 0.2,
            base_color_texture: (i == 5).then(|| bad.clone()),
            ..Material::default()
        })
        .collect();
    let mesh = grid_mesh(32, 32, 1, [2.0, 2.0], materials);
    assert!(!mesh.has_uvs && !mesh.has_normals);
    let built = build(&mesh, &BuildOptions::default()).expect("grid builds");
    let ctx = gpu();
    let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &white_placement())
        .expect("renderer");
    r.set_count_fragments(true);
    let warnings = r.prepare_materials().expect("materials upload");
    eprintln!("warnings: {warnings:?}");
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("not_an_image.png") && w.contains("m5")),
        "the unreadable texture is reported with its material"
    );
    let camera = front_camera(2.3);
    for mode in ViewMode::MATERIAL {
        let f = r
            .render(&camera, W, H, &exact(), mode, &Light::default())
            .expect("frame with 1,024 materials");
        f.check().expect("complete frame");
        let passes = r.material_passes().expect("material passes");
        let counts = passes.fragment_counts().expect("counts");
        let covered = f.visbuffer.iter().filter(|&&v| v != 0).count();
        let total: u64 = counts.iter().map(|&c| c as u64).sum();
        assert_eq!(
            total, covered as u64,
            "{mode:?}: every covered pixel shaded once"
        );
        let with_pixels = counts.iter().filter(|&&c| c > 0).count();
        let distinct: std::collections::BTreeSet<&[u8]> = f.frame.color.chunks(4).collect();
        eprintln!(
            "{mode:?}: {with_pixels} materials drawn, {covered} covered pixels, {} colours",
            distinct.len()
        );
        assert!(
            with_pixels >= 1000,
            "{mode:?}: {with_pixels} materials on screen"
        );
        if mode != ViewMode::Normals {
            assert!(distinct.len() > 200, "{mode:?}: {} colours", distinct.len());
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert_no_validation_errors(&ctx);
}

#[test]
fn cli_renders_the_material_views() {
    let dir = std::env::temp_dir().join(format!("vgeo-material-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let mut images = Vec::new();
    for view in ["lit", "albedo", "normals", "materials"] {
        let out = dir.join(format!("{view}.png"));
        let result = std::process::Command::new(env!("CARGO_BIN_EXE_vgeo"))
            .env("VGEO_VALIDATION", "1")
            .arg("render")
            .arg(assets().join("spot.obj"))
            .args([
                "--mode", "vgeo", "--view", view, "--width", "96", "--height", "64",
            ])
            .args(["--error-px", "1", "--stats", "-o"])
            .arg(&out)
            .output()
            .expect("vgeo runs");
        let stderr = String::from_utf8_lossy(&result.stderr);
        let stdout = String::from_utf8_lossy(&result.stdout);
        assert!(result.status.success(), "--view {view} failed: {stderr}");
        assert!(
            !stderr.contains("validation error"),
            "--view {view}: {stderr}"
        );
        for pass in ["material_classify", "emit_gbuffer", "shade"] {
            assert!(
                stdout.contains(pass),
                "--view {view}: no timing of {pass}: {stdout}"
            );
        }
        let img = image::open(&out).expect("PNG written").to_rgba8();
        assert_eq!(img.dimensions(), (96, 64));
        images.push(img.into_raw());
    }
    for i in 0..images.len() {
        for j in i + 1..images.len() {
            assert_ne!(images[i], images[j], "views {i} and {j} look the same");
        }
    }
    let result = std::process::Command::new(env!("CARGO_BIN_EXE_vgeo"))
        .arg("render")
        .arg(assets().join("spot.obj"))
        .args(["--mode", "vgeo", "--view", "bogus", "-o"])
        .arg(dir.join("bogus.png"))
        .output()
        .expect("vgeo runs");
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(!result.status.success());
    assert!(
        stderr.contains("lit") && stderr.contains("lambert") && stderr.contains("materials"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// PSNR (dB) of two RGBA8 images over the RGB channels of every pixel.
fn psnr(a: &[u8], b: &[u8]) -> f64 {
    assert_eq!(a.len(), b.len());
    let (mut se, mut n) = (0.0f64, 0usize);
    for (pa, pb) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
        for k in 0..3 {
            let d = pa[k] as f64 - pb[k] as f64;
            se += d * d;
            n += 1;
        }
    }
    10.0 * (255.0f64 * 255.0 / (se / n as f64).max(1e-12)).log10()
}

/// Renders `meshes` placed by `placements` from `camera` with vgeo at threshold 0, brute and lod
/// at threshold 0 (lit, the material model), returns (vgeo, brute, lod) colour and vgeo's frame.
fn lit_in_every_mode(
    meshes: &[Mesh],
    placements: &[Placement],
    camera: &Camera,
    w: u32,
    h: u32,
) -> (VgeoFrame, Vec<u8>, Vec<u8>) {
    let built: Vec<BuiltMesh> = meshes
        .iter()
        .map(|m| build(m, &BuildOptions::default()).expect("builds"))
        .collect();
    let ctx = gpu();
    let light = Light::default();
    let mut r = VgeoRenderer::new(&ctx, &built, placements).expect("renderer");
    let f = r
        .render(camera, w, h, &exact(), ViewMode::Lit, &light)
        .expect("vgeo frame");
    f.check().expect("complete frame");
    let brute = Brute::new(&ctx, meshes).expect("brute");
    let b = brute
        .render(placements, camera, &light, w, h)
        .expect("brute frame");
    let lod = Lod::new(&ctx, meshes, &LodOptions::default()).expect("lod");
    let l = lod
        .render(placements, camera, &light, w, h, 0.0)
        .expect("lod frame");
    assert_no_validation_errors(&ctx);
    (f, b.color, l.color)
}

fn dump(name: &str, w: u32, h: u32, rgba: &[u8]) {
    if let Ok(dir) = std::env::var("VGEO_TEST_DUMP") {
        image::RgbaImage::from_raw(w, h, rgba.to_vec())
            .expect("size")
            .save(std::path::Path::new(&dir).join(name))
            .expect("dump");
    }
}

#[test]
fn flight_helmet_lit_vgeo_matches_brute_and_lod() {
    const W: u32 = 256;
    const H: u32 = 256;
    let path = shared_assets().join("gltf/FlightHelmet/FlightHelmet.gltf");
    let (mesh, _) = vgeo::mesh::load_mesh(&path).expect("FlightHelmet loads");
    assert!(mesh.materials.len() >= 5, "FlightHelmet has its materials");
    let (lo, hi) = mesh.bounds().expect("bounds");
    let camera = Camera::frame_bounds(
        DVec3::from(lo.map(f64::from)),
        DVec3::from(hi.map(f64::from)),
        W as f32 / H as f32,
    );
    let placements = vec![Placement {
        mesh: 0,
        transform: DMat4::IDENTITY,
        color: [1.0, 0.95, 0.9],
    }];
    let (f, brute, lod) =
        lit_in_every_mode(std::slice::from_ref(&mesh), &placements, &camera, W, H);
    dump("lit_helmet_vgeo.png", W, H, &f.frame.color);
    dump("lit_helmet_brute.png", W, H, &brute);
    let covered = f.visbuffer.iter().filter(|&&v| v != 0).count();
    assert!(covered > (W * H / 8) as usize, "the helmet covers the view");
    let p = psnr(&f.frame.color, &brute);
    eprintln!("FlightHelmet lit, threshold 0: vgeo vs brute PSNR {p:.2} dB ({covered} covered)");
    assert!(p >= 40.0, "vgeo vs brute PSNR {p:.2} dB < 40 dB");
    // lod at threshold 0 draws level 0: the same triangles through the same pipeline.
    assert_eq!(lod, brute, "lod at threshold 0 is brute's image");
}

/// A wavy `n` x `n` grid with shared vertices over x, y in [-1, 1] (z = 0.1 sin), UVs (u repeating
/// once per region column, v over the grid), analytic normals, and a material per region of a 4 x 2 partition (`materials.len()`
/// must be 8): neighbouring regions share their border vertices.
fn wavy_grid(n: u32, materials: Vec<Material>) -> Mesh {
    assert_eq!(materials.len(), 8);
    let mut m = Mesh {
        name: "wavy".into(),
        materials,
        has_normals: true,
        has_uvs: true,
        ..Default::default()
    };
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            let (x, y) = (u * 2.0 - 1.0, 1.0 - v * 2.0);
            let z = 0.1 * (3.0 * x).sin() * (2.0 * y).cos();
            let dzdx = 0.3 * (3.0 * x).cos() * (2.0 * y).cos();
            let dzdy = -0.2 * (3.0 * x).sin() * (2.0 * y).sin();
            m.positions.push([x, y, z]);
            m.normals
                .push(Vec3::new(-dzdx, -dzdy, 1.0).normalize().to_array());
            m.uvs.push([u * 4.0, v]);
        }
    }
    let row = n + 1;
    for j in 0..n {
        for i in 0..n {
            let a = j * row + i;
            let (b, c, d) = (a + 1, a + row, a + row + 1);
            m.indices.extend_from_slice(&[a, c, b, b, c, d]);
            let mat = (j * 2 / n) * 4 + i * 4 / n;
            m.material_ids.extend_from_slice(&[mat, mat]);
        }
    }
    m.validate().expect("wavy grid is valid");
    m
}

#[test]
fn multi_material_scene_lit_vgeo_matches_brute() {
    const W: u32 = 256;
    const H: u32 = 192;
    let dir = std::env::temp_dir().join(format!("vgeo-lit-modes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let helmet = shared_assets().join("gltf/FlightHelmet");
    let write = |name: &str, img: image::RgbaImage| {
        let path = dir.join(name);
        img.save(&path).expect("write texture");
        path
    };
    // Metallic-roughness: left half dielectric and rough, right half metal and smooth.
    let mr = write(
        "mr.png",
        image::RgbaImage::from_fn(16, 16, |x, _| {
            if x < 8 {
                image::Rgba([0, 255, 0, 255])
            } else {
                image::Rgba([0, 90, 255, 255])
            }
        }),
    );
    let normal = write(
        "n.png",
        image::RgbaImage::from_fn(16, 16, |x, y| {
            image::Rgba([128 + (x * 6) as u8, 128 + (y * 4) as u8, 230, 255])
        }),
    );
    let materials: Vec<Material> = (0..8)
        .map(|i| Material {
            name: format!("m{i}"),
            base_color: [0.3 + 0.1 * i as f32, 0.9 - 0.1 * i as f32, 0.5, 1.0],
            metallic: [0.0, 0.0, 1.0, 0.5, 0.0, 1.0, 0.2, 0.0][i],
            roughness: 0.3 + 0.09 * i as f32,
            base_color_texture: match i {
                0..=3 => Some(helmet.join(format!(
                    "FlightHelmet_baseColor{}.png",
                    ["", "2", "3", "4"][i]
                ))),
                _ => None,
            },
            normal_texture: (i == 1 || i == 6).then(|| normal.clone()),
            metallic_roughness_texture: (i == 5).then(|| mr.clone()),
        })
        .collect();
    let grid = wavy_grid(48, materials);
    let (spot, _) = vgeo::mesh::load_mesh(&assets().join("spot.obj")).expect("spot loads");
    let placements = vec![
        Placement {
            mesh: 0,
            transform: DMat4::from_rotation_x(-0.5),
            color: [1.0; 3],
        },
        Placement {
            mesh: 1,
            transform: DMat4::from_translation(DVec3::new(0.4, 0.2, 0.6))
                * DMat4::from_scale(DVec3::splat(0.5)),
            color: [0.9, 0.8, 1.0],
        },
    ];
    let camera = Camera::look_at(
        DVec3::new(0.2, 0.9, 2.6),
        DVec3::new(0.0, 0.0, 0.2),
        Vec3::Y,
        45f32.to_radians(),
        0.05,
    );
    let meshes = [grid, spot];
    let (f, brute, lod) = lit_in_every_mode(&meshes, &placements, &camera, W, H);
    dump("lit_multi_vgeo.png", W, H, &f.frame.color);
    dump("lit_multi_brute.png", W, H, &brute);
    // Every material of the grid and the cow are in view.
    let built: Vec<BuiltMesh> = meshes
        .iter()
        .map(|m| build(m, &BuildOptions::default()).expect("builds"))
        .collect();
    let mats = SceneMaterials::new(&built).expect("materials");
    let per_pixel = cpu_pixel_materials(&f, &built, &placements, &mats);
    let mut seen = vec![0usize; mats.materials.len()];
    for &m in per_pixel.iter().filter(|&&m| m != NO_MATERIAL) {
        seen[m as usize] += 1;
    }
    eprintln!("pixels per material: {seen:?}");
    assert!(seen.iter().all(|&n| n > 100), "every material in view");
    let p = psnr(&f.frame.color, &brute);
    eprintln!("multi-material scene lit, threshold 0: vgeo vs brute PSNR {p:.2} dB");
    assert!(p >= 40.0, "vgeo vs brute PSNR {p:.2} dB < 40 dB");
    assert_eq!(lod, brute, "lod at threshold 0 is brute's image");
    // The metallic-roughness texture is read: on material 5's pixels, the metal half (no diffuse
    // term) is darker than the dielectric half in both paths.
    for (name, img) in [("vgeo", &f.frame.color), ("brute", &brute)] {
        let (mut sums, mut counts) = ([0.0f64; 2], [0usize; 2]);
        for (i, &m) in per_pixel.iter().enumerate() {
            if m != 5 {
                continue;
            }
            let x = i as u32 % W;
            // Material 5's region spans one repeat of the texture in u: its left and right
            // halves on screen are the texture's halves.
            let half = usize::from(x as f32 >= region_center_x(&per_pixel, W, 5));
            sums[half] += img[4 * i..4 * i + 3].iter().map(|&c| c as f64).sum::<f64>();
            counts[half] += 1;
        }
        let (left, right) = (sums[0] / counts[0] as f64, sums[1] / counts[1] as f64);
        eprintln!("{name}: material 5 mean left {left:.1}, right {right:.1}");
        assert!(left > right * 1.3, "{name}: the metal half is darker");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Mean screen x of the pixels of material `m`.
fn region_center_x(per_pixel: &[u32], w: u32, m: u32) -> f32 {
    let xs: Vec<f32> = per_pixel
        .iter()
        .enumerate()
        .filter(|&(_, &p)| p == m)
        .map(|(i, _)| (i as u32 % w) as f32)
        .collect();
    xs.iter().sum::<f32>() / xs.len().max(1) as f32
}

#[test]
fn classic_mesh_splits_shared_vertices_by_material() {
    let materials: Vec<Material> = (0..8)
        .map(|i| Material {
            name: format!("m{i}"),
            ..Material::default()
        })
        .collect();
    let mesh = wavy_grid(8, materials);
    let split = vgeo::baseline::brute::ClassicMesh::new(&mesh);
    let s = &split.mesh;
    assert_eq!(s.indices.len(), mesh.indices.len());
    assert!(
        s.positions.len() > mesh.positions.len(),
        "border vertices are duplicated"
    );
    // Borders of a 4 x 2 partition of an 8 x 8 grid: 3 vertical lines of 9 vertices and 1
    // horizontal one, crossing at 3 vertices. A border vertex is in 2 regions (1 extra copy), a
    // crossing in 4 (3 extra copies).
    assert_eq!(
        s.positions.len() - mesh.positions.len(),
        (3 * 9 - 3) + (9 - 3) + 3 * 3
    );
    for (t, (a, b)) in mesh
        .indices
        .chunks_exact(3)
        .zip(s.indices.chunks_exact(3))
        .enumerate()
    {
        for k in 0..3 {
            assert_eq!(s.positions[b[k] as usize], mesh.positions[a[k] as usize]);
            assert_eq!(s.uvs[b[k] as usize], mesh.uvs[a[k] as usize]);
            assert_eq!(split.vertex_materials[b[k] as usize], mesh.material_ids[t]);
        }
    }
    let single = Mesh {
        materials: vec![Material::default()],
        material_ids: vec![0; mesh.material_ids.len()],
        ..mesh.clone()
    };
    let same = vgeo::baseline::brute::ClassicMesh::new(&single);
    assert!(matches!(same.mesh, std::borrow::Cow::Borrowed(_)));
}
