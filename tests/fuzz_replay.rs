//! Replays the fuzz corpora (`fuzz/corpus/<target>/`) and the inputs the fuzzers found crashing
//! (`fuzz/regressions/<target>/`) through the fuzz targets' own entry points, on stable and
//! without libFuzzer: no file may panic, and each regression file must end the way its fix says
//! (an error or a warning naming what is wrong).

#[allow(dead_code)]
#[path = "../fuzz/src/lib.rs"]
mod entry;

use std::path::{Path, PathBuf};

use entry::Outcome;
use vgeo::mesh::Format;

/// A fuzz target's entry point.
type Entry = fn(&[u8]) -> Outcome;

/// The fuzz targets: name and entry point (as in `fuzz/fuzz_targets/<name>.rs`).
const TARGETS: &[(&str, Entry)] = &[
    ("import_obj", |d| entry::import(Format::Obj, "fuzz.obj", d)),
    ("import_ply", |d| entry::import(Format::Ply, "fuzz.ply", d)),
    ("import_stl", |d| entry::import(Format::Stl, "fuzz.stl", d)),
    ("import_off", |d| entry::import(Format::Off, "fuzz.off", d)),
    ("import_gltf", |d| {
        entry::import(Format::Gltf, "fuzz.gltf", d)
    }),
    ("import_glb", |d| entry::import(Format::Gltf, "fuzz.glb", d)),
    ("load_vgeo", entry::load_vgeo),
];

/// How a regression file must end.
enum Expect {
    /// An error containing every string.
    Refused(&'static [&'static str]),
    /// Loaded, with a warning containing every string.
    Warned(&'static [&'static str]),
}

/// Every file under `fuzz/regressions/`: target, file name, expected outcome.
const REGRESSIONS: &[(&str, &str, Expect)] = &[
    // A page whose cluster header used wider fields than its vertices need decoded fine, but
    // saving the loaded mesh re-encoded it shorter than its page record said: the saved file did
    // not load (vgeo_fuzz::load_vgeo). The loader now accepts only the minimal code. (Found as
    // a version-5 file; remade as version 9, a width per normal component, by
    // fuzz/widen_cluster_code.py from the seed tetra_and_triangle.vgeo: the same defect.)
    (
        "load_vgeo",
        "non_minimal_cluster_code.vgeo",
        Expect::Refused(&["page 0", "not the minimal code of its vertices"]),
    ),
    // A cluster whose normals' y width (format 9: above the triangle code's header in its
    // smallest x coordinate) is over 16 bits, among other damage: a debug assertion in
    // `page::cull_words`, in a draft of that change, fired on it before the loader compared the
    // cull words (found by load_vgeo in its first 21,000 runs; the assertion now sits in the
    // encoder). The loader refuses it. (tests/builder.rs refuses a width over 16 alone.)
    (
        "load_vgeo",
        "normal_y_width_out_of_range.vgeo",
        Expect::Refused(&["page 0", "cull words", "differ from its record"]),
    ),
    // tobj-4.0.5 turned the relative normal reference -13 (of 1 normal) into an index near
    // usize::MAX and multiplied it: overflow (src/lib.rs:860). References are checked first.
    (
        "import_obj",
        "relative_normal_reference_past_start.obj",
        Expect::Refused(&["line 14", "bad normal reference '-13' (1 defined so far)"]),
    ),
    // 2.5 KB naming one 2^20-vertex accessor (zeros and a sparse substitution) from 64
    // primitives or 64 nodes asked for gigabytes (out of memory under the fuzzer's 2 GB limit).
    (
        "import_gltf",
        "one_accessor_in_64_primitives.gltf",
        Expect::Refused(&[
            "expands",
            "8388608 vertices and triangle corners",
            "hostile",
        ]),
    ),
    (
        "import_gltf",
        "one_accessor_in_64_nodes.gltf",
        Expect::Refused(&[
            "expands",
            "8388608 vertices and triangle corners",
            "hostile",
        ]),
    ),
    // gltf-1.4.1 `Image::source` unwrapped the missing uri (src/image.rs:128).
    (
        "import_glb",
        "image_without_uri_or_buffer_view.glb",
        Expect::Warned(&["material 'm'", "base-colour", "image 0", "neither"]),
    ),
    // gltf-1.4.1 `Image::source` unwrapped the missing mimeType (src/image.rs:125).
    (
        "import_glb",
        "image_in_buffer_view_without_mime_type.glb",
        Expect::Warned(&["material 'm'", "base-colour", "embedded"]),
    ),
    // gltf-1.4.1 `Gltf::from_slice` took the JSON chunk for a nested GLB and subtracted with
    // overflow (src/binary.rs:252).
    (
        "import_glb",
        "nested_glb_header_in_json_chunk.glb",
        Expect::Refused(&["invalid glTF"]),
    ),
];

fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz")
}

/// The files of `dir`, sorted; none if it does not exist.
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = match std::fs::read_dir(dir) {
        Ok(rd) => rd
            .map(|e| e.expect("directory entry").path())
            .filter(|p| p.is_file())
            .collect(),
        Err(_) => Vec::new(),
    };
    v.sort();
    v
}

/// Runs `f` on `path`'s bytes, turning a panic into a test failure that names the file.
fn replay(target: &str, f: Entry, path: &Path) -> Outcome {
    let data = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    std::panic::catch_unwind(|| f(&data)).unwrap_or_else(|_| {
        panic!(
            "{target}: {} panicked (replay with `cargo +nightly fuzz run {target} {}` in fuzz/)",
            path.display(),
            path.display()
        )
    })
}

#[test]
fn every_corpus_file_replays_without_panic() {
    let mut total = 0;
    for (target, f) in TARGETS {
        let corpus = files(&fuzz_dir().join("corpus").join(target));
        assert!(!corpus.is_empty(), "{target}: no seed corpus");
        let loaded = corpus
            .iter()
            .filter(|p| matches!(replay(target, *f, p), Outcome::Loaded { .. }))
            .count();
        // The seeds are mostly valid files: the fuzzer mutates working inputs.
        assert!(loaded > 0, "{target}: no seed loads");
        total += corpus.len();
    }
    assert!(total >= 7 * 4, "{total} seeds");
}

#[test]
fn every_regression_file_ends_as_its_fix_says() {
    let mut seen = Vec::new();
    for (target, f) in TARGETS {
        for path in files(&fuzz_dir().join("regressions").join(target)) {
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            let Some((_, _, expect)) = REGRESSIONS
                .iter()
                .find(|(t, n, _)| t == target && *n == name)
            else {
                panic!("{target}/{name}: not listed in REGRESSIONS with its expected outcome");
            };
            seen.push((target.to_string(), name.clone()));
            let outcome = replay(target, *f, &path);
            match (expect, &outcome) {
                (Expect::Refused(want), Outcome::Refused(message)) => {
                    for w in *want {
                        assert!(
                            message.contains(w),
                            "{target}/{name}: {message:?} lacks {w:?}"
                        );
                    }
                }
                (Expect::Warned(want), Outcome::Loaded { warnings }) => {
                    assert!(
                        warnings.iter().any(|m| want.iter().all(|w| m.contains(w))),
                        "{target}/{name}: no warning with {want:?} in {warnings:?}"
                    );
                }
                _ => panic!("{target}/{name}: unexpected outcome {outcome:?}"),
            }
        }
    }
    for (target, name, _) in REGRESSIONS {
        assert!(
            seen.iter().any(|(t, n)| t == target && n == name),
            "{target}/{name} is listed but missing from fuzz/regressions/"
        );
    }
}
