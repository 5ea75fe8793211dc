//! Shaders without a rebuild: `--shader-dir DIR` (or `VGEO_SHADER_DIR`) compiles GLSL from `DIR` at
//! start-up with the shaderc vgeo links, in place of the SPIR-V embedded at build time.
//!
//! `DIR` mirrors `shaders_glsl/`: a pass's file (`shade.comp.glsl`) or an include
//! (`common/shading.glsl`) placed there replaces the built-in one; every other file comes from the
//! sources embedded in the binary, so one edited file is enough. Every shader whose file or any of
//! its includes is replaced is compiled again, with the same macros as build.rs (src/shared.rs's
//! constants and the variant's macro; `SHADER_DEBUG=1` for debug info). Then the interface blocks
//! of the new SPIR-V (push constants, uniform and storage blocks by set and binding) are
//! reflected and checked against the embedded shader's: the Rust structs were written for those
//! sizes, so a block that changed size is an error, not a wrong image.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use crate::shaders::{DEFINES, SOURCES, VARIANTS};

/// The SPIR-V compiled from a shader folder, keyed by the embedded SPIR-V it replaces.
#[derive(Debug, Default)]
pub struct ShaderOverrides {
    /// (embedded SPIR-V, shader name, replacement SPIR-V). Found by content: a `const` slice's
    /// address is not guaranteed to be the same at every use.
    by_embedded: Vec<(&'static [u8], String, Vec<u8>)>,
}

/// The files of a shader folder over the embedded sources.
struct Sources<'a> {
    dir: &'a Path,
    /// Relative path -> the folder's text, for the files the folder replaces.
    replaced: HashMap<String, String>,
}

impl Sources<'_> {
    /// The text of `rel` (a path relative to `shaders_glsl/`) and the name errors give it.
    fn get(&self, rel: &str) -> Option<(String, String)> {
        if let Some(text) = self.replaced.get(rel) {
            return Some((self.dir.join(rel).display().to_string(), text.clone()));
        }
        SOURCES
            .iter()
            .find(|(p, _)| *p == rel)
            .map(|(p, t)| (format!("shaders_glsl/{p} (built in)"), t.to_string()))
    }

    /// Resolves `#include "requested"` from the file `requester` (relative path) as build.rs does:
    /// beside the requester, at the root, in `common/`.
    fn resolve(&self, requested: &str, requester: &str) -> Option<String> {
        let base = Path::new(requester)
            .parent()
            .map(|p| p.to_string_lossy().to_string())
            .unwrap_or_default();
        let join = |a: &str, b: &str| {
            if a.is_empty() {
                b.to_string()
            } else {
                format!("{a}/{b}")
            }
        };
        [
            join(&base, requested),
            requested.to_string(),
            join("common", requested),
        ]
        .into_iter()
        .find(|c| self.replaced.contains_key(c) || SOURCES.iter().any(|(p, _)| p == c))
    }

    /// `rel` and every file it includes, transitively.
    fn closure(&self, rel: &str) -> HashSet<String> {
        let mut seen = HashSet::new();
        let mut todo = vec![rel.to_string()];
        while let Some(f) = todo.pop() {
            if !seen.insert(f.clone()) {
                continue;
            }
            let Some((_, text)) = self.get(&f) else {
                continue;
            };
            for line in text.lines() {
                if let Some(req) = include_target(line)
                    && let Some(r) = self.resolve(req, &f)
                {
                    todo.push(r);
                }
            }
        }
        seen
    }
}

/// The file named by an `#include "x"` line.
fn include_target(line: &str) -> Option<&str> {
    let rest = line.trim_start().strip_prefix('#')?.trim_start();
    let rest = rest.strip_prefix("include")?.trim();
    rest.strip_prefix('"')?.split('"').next()
}

/// Every `*.glsl` under `dir` (and `dir/common`), as relative paths with their text.
fn read_dir(dir: &Path) -> Result<HashMap<String, String>, String> {
    if !dir.is_dir() {
        return Err(format!(
            "shader folder {} does not exist or is not a folder",
            dir.display()
        ));
    }
    let mut out = HashMap::new();
    for sub in ["", "common"] {
        let d = dir.join(sub);
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let path = e.path();
            if path.extension().is_none_or(|x| x != "glsl") || !path.is_file() {
                continue;
            }
            let name = path.file_name().unwrap_or_default().to_string_lossy();
            let rel = if sub.is_empty() {
                name.to_string()
            } else {
                format!("{sub}/{name}")
            };
            if !SOURCES.iter().any(|(p, _)| *p == rel) {
                let known: Vec<&str> = SOURCES.iter().map(|(p, _)| *p).collect();
                return Err(format!(
                    "{}: not a vgeo shader source (the folder mirrors shaders_glsl/: {})",
                    path.display(),
                    known.join(", ")
                ));
            }
            let text = std::fs::read_to_string(&path)
                .map_err(|e| format!("reading {}: {e}", path.display()))?;
            out.insert(rel, text);
        }
    }
    Ok(out)
}

impl ShaderOverrides {
    /// Compiles every shader that `dir` changes (its file or an include). Errors name the file
    /// and line (shaderc's `file:line: error: ...`), or the block whose size changed.
    pub fn compile(dir: &Path, debug: bool) -> Result<Self, String> {
        let sources = Sources {
            dir,
            replaced: read_dir(dir)?,
        };
        let mut out = Self {
            by_embedded: Vec::new(),
        };
        if sources.replaced.is_empty() {
            return Ok(out);
        }
        let compiler = shaderc::Compiler::new()
            .ok_or_else(|| "the shaderc compiler could not be created".to_string())?;
        let mut errors = Vec::new();
        for v in VARIANTS {
            let closure = sources.closure(v.file);
            if !closure.iter().any(|f| sources.replaced.contains_key(f)) {
                continue;
            }
            let name = match v.define {
                Some((k, _)) => format!("{} ({k})", v.file),
                None => v.file.to_string(),
            };
            match compile_one(&compiler, &sources, v.file, v.define, debug) {
                Ok(spirv) => match check_blocks(v.spirv, &spirv) {
                    Ok(()) => {
                        out.by_embedded.push((v.spirv, name, spirv));
                    }
                    Err(e) => errors.push(format!("{name}: {e}")),
                },
                Err(e) => errors.push(e),
            }
        }
        if errors.is_empty() {
            Ok(out)
        } else {
            Err(format!(
                "shaders in {} failed:\n{}",
                dir.display(),
                errors.join("\n")
            ))
        }
    }

    /// The shaders compiled from the folder (file, and the variant's macro).
    pub fn names(&self) -> Vec<String> {
        let mut v: Vec<String> = self.by_embedded.iter().map(|(_, n, _)| n.clone()).collect();
        v.sort();
        v
    }

    /// The replacement for the embedded SPIR-V `embedded` (one of `crate::shaders`' constants),
    /// if the folder changed it.
    pub fn replacement(&self, embedded: &[u8]) -> Option<&[u8]> {
        self.by_embedded
            .iter()
            .find(|(e, _, _)| *e == embedded)
            .map(|(_, _, s)| s.as_slice())
    }
}

fn compile_one(
    compiler: &shaderc::Compiler,
    sources: &Sources<'_>,
    file: &str,
    define: Option<(&str, &str)>,
    debug: bool,
) -> Result<Vec<u8>, String> {
    let (input_name, text) = sources
        .get(file)
        .ok_or_else(|| format!("{file}: no such shader source"))?;
    let stage = file.trim_end_matches(".glsl").rsplit('.').next();
    let kind = stage
        .and_then(super::shaderc_options::shader_kind)
        .ok_or_else(|| format!("{file}: unknown shader stage"))?;
    let mut macros: Vec<(&str, &str)> = DEFINES.to_vec();
    macros.extend(define);
    let mut opts = super::shaderc_options::compile_options(debug, &macros)
        .ok_or_else(|| "shaderc options could not be created".to_string())?;
    // shaderc names includes by what the callback returns; keep the relative path there (for
    // further includes) and map it back to a readable name in errors.
    let mut names: Vec<(String, String)> = Vec::new();
    for rel in sources.closure(file) {
        if let Some((shown, _)) = sources.get(&rel) {
            names.push((rel, shown));
        }
    }
    let resolver = Sources {
        dir: sources.dir,
        replaced: sources.replaced.clone(),
    };
    let file_rel = file.to_string();
    opts.set_include_callback(move |requested, _ty, requester, _depth| {
        let requester = if requester == input_name_placeholder() {
            file_rel.as_str()
        } else {
            requester
        };
        let rel = resolver
            .resolve(requested, requester)
            .ok_or_else(|| format!("cannot find include `{requested}`"))?;
        let (_, content) = resolver
            .get(&rel)
            .ok_or_else(|| format!("cannot read include `{requested}`"))?;
        Ok(shaderc::ResolvedInclude {
            resolved_name: rel,
            content,
        })
    });
    match compiler.compile_into_spirv(&text, kind, input_name_placeholder(), "main", Some(&opts)) {
        Ok(art) => Ok(art.as_binary_u8().to_vec()),
        Err(e) => {
            // Errors read `name:line: error: ...`; give each file its shown name.
            let msg = e
                .to_string()
                .lines()
                .map(|line| {
                    if let Some(rest) = line.strip_prefix(input_name_placeholder()) {
                        return format!("{input_name}{rest}");
                    }
                    for (rel, shown) in &names {
                        if let Some(rest) = line.strip_prefix(rel.as_str())
                            && rest.starts_with(':')
                        {
                            return format!("{shown}{rest}");
                        }
                    }
                    line.to_string()
                })
                .collect::<Vec<_>>()
                .join("\n");
            Err(msg)
        }
    }
}

/// The name the main file has inside shaderc (replaced by its path in errors).
fn input_name_placeholder() -> &'static str {
    "<vgeo-shader-main>"
}

/// Interface block sizes by where they are bound: push constants, or (set, binding).
fn check_blocks(embedded: &[u8], new: &[u8]) -> Result<(), String> {
    let a = block_sizes(embedded).map_err(|e| format!("built-in SPIR-V: {e}"))?;
    let b = block_sizes(new)?;
    let mut bad = Vec::new();
    for (key, size) in &b {
        if let Some(old) = a.get(key)
            && old != size
        {
            bad.push(format!(
                "{key} is {size} bytes, the built-in shader's (and vgeo's struct) {old} bytes"
            ));
        }
    }
    bad.sort();
    if bad.is_empty() {
        Ok(())
    } else {
        Err(format!("interface blocks changed size: {}", bad.join("; ")))
    }
}

/// Reflects the byte size of every push-constant, uniform and storage block of a SPIR-V module
/// (the fixed part of a block ending in a runtime array), keyed `push constants` or
/// `set S binding B`.
pub(crate) fn block_sizes(spirv: &[u8]) -> Result<HashMap<String, u32>, String> {
    if !spirv.len().is_multiple_of(4) || spirv.len() < 20 {
        return Err("not SPIR-V (length)".into());
    }
    let words: Vec<u32> = spirv
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    if words[0] != 0x0723_0203 {
        return Err("not SPIR-V (magic)".into());
    }
    #[derive(Clone)]
    enum Ty {
        Scalar(u32),
        Vector(u32, u32),
        Matrix(u32, u32),
        Array(u32, u32),
        RuntimeArray(u32),
        Struct(Vec<u32>),
        Pointer(u32),
        Other,
    }
    let mut types: HashMap<u32, Ty> = HashMap::new();
    let mut constants: HashMap<u32, u32> = HashMap::new();
    let mut array_stride: HashMap<u32, u32> = HashMap::new();
    let mut offsets: HashMap<(u32, u32), u32> = HashMap::new();
    let mut matrix_stride: HashMap<(u32, u32), u32> = HashMap::new();
    let mut set: HashMap<u32, u32> = HashMap::new();
    let mut binding: HashMap<u32, u32> = HashMap::new();
    let mut variables: Vec<(u32, u32, u32)> = Vec::new();
    let mut i = 5;
    while i < words.len() {
        let count = (words[i] >> 16) as usize;
        let op = words[i] & 0xffff;
        if count == 0 || i + count > words.len() {
            return Err("not SPIR-V (instruction length)".into());
        }
        let w = &words[i + 1..i + count];
        let at = |k: usize| w.get(k).copied().unwrap_or(0);
        match op {
            20 => {
                types.insert(at(0), Ty::Scalar(4));
            }
            21 | 22 => {
                types.insert(at(0), Ty::Scalar(at(1) / 8));
            }
            23 => {
                types.insert(at(0), Ty::Vector(at(1), at(2)));
            }
            24 => {
                types.insert(at(0), Ty::Matrix(at(1), at(2)));
            }
            28 => {
                types.insert(at(0), Ty::Array(at(1), at(2)));
            }
            29 => {
                types.insert(at(0), Ty::RuntimeArray(at(1)));
            }
            30 => {
                types.insert(at(0), Ty::Struct(w.get(1..).unwrap_or(&[]).to_vec()));
            }
            32 => {
                types.insert(at(0), Ty::Pointer(at(2)));
            }
            43 => {
                constants.insert(at(1), at(2));
            }
            59 => variables.push((at(0), at(1), at(2))),
            71 => match at(1) {
                6 => {
                    array_stride.insert(at(0), at(2));
                }
                33 => {
                    binding.insert(at(0), at(2));
                }
                34 => {
                    set.insert(at(0), at(2));
                }
                _ => {}
            },
            72 => match at(2) {
                35 => {
                    offsets.insert((at(0), at(1)), at(3));
                }
                7 => {
                    matrix_stride.insert((at(0), at(1)), at(3));
                }
                _ => {}
            },
            _ => {
                if (19..=39).contains(&op) && op != 43 && !types.contains_key(&at(0)) {
                    types.insert(at(0), Ty::Other);
                }
            }
        }
        i += count;
    }
    fn size(
        id: u32,
        types: &HashMap<u32, Ty>,
        constants: &HashMap<u32, u32>,
        array_stride: &HashMap<u32, u32>,
        offsets: &HashMap<(u32, u32), u32>,
        matrix_stride: &HashMap<(u32, u32), u32>,
        depth: u32,
    ) -> u32 {
        if depth > 32 {
            return 0;
        }
        let rec = |t: u32| {
            size(
                t,
                types,
                constants,
                array_stride,
                offsets,
                matrix_stride,
                depth + 1,
            )
        };
        match types.get(&id) {
            Some(Ty::Scalar(s)) => *s,
            Some(Ty::Vector(c, n)) => rec(*c) * n,
            Some(Ty::Matrix(col, n)) => rec(*col) * n,
            Some(Ty::Array(e, len)) => {
                let n = constants.get(len).copied().unwrap_or(0);
                let stride = array_stride.get(&id).copied().unwrap_or_else(|| rec(*e));
                stride * n
            }
            Some(Ty::RuntimeArray(_)) => 0,
            Some(Ty::Struct(members)) => members
                .iter()
                .enumerate()
                .map(|(m, &t)| {
                    let off = offsets.get(&(id, m as u32)).copied().unwrap_or(0);
                    let sz = match (types.get(&t), matrix_stride.get(&(id, m as u32))) {
                        (Some(Ty::Matrix(_, n)), Some(s)) => s * n,
                        _ => rec(t),
                    };
                    off + sz
                })
                .max()
                .unwrap_or(0),
            _ => 0,
        }
    }
    let mut out = HashMap::new();
    for (ptr_ty, id, class) in variables {
        // Uniform (2), PushConstant (9), StorageBuffer (12).
        if !matches!(class, 2 | 9 | 12) {
            continue;
        }
        let Some(Ty::Pointer(mut pointee)) = types.get(&ptr_ty).cloned() else {
            continue;
        };
        // Arrays of blocks: the element.
        if let Some(Ty::Array(e, _) | Ty::RuntimeArray(e)) = types.get(&pointee) {
            pointee = *e;
        }
        let bytes = size(
            pointee,
            &types,
            &constants,
            &array_stride,
            &offsets,
            &matrix_stride,
            0,
        );
        let key = if class == 9 {
            "push constants".to_string()
        } else {
            format!(
                "set {} binding {}",
                set.get(&id).copied().unwrap_or(0),
                binding.get(&id).copied().unwrap_or(0)
            )
        };
        out.insert(key, bytes);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn include_lines_are_parsed() {
        assert_eq!(
            include_target("#include \"shared.glsl\""),
            Some("shared.glsl")
        );
        assert_eq!(
            include_target("  # include \"a/b.glsl\" // x"),
            Some("a/b.glsl")
        );
        assert_eq!(include_target("// #include \"x\""), None);
    }

    #[test]
    fn embedded_shaders_reflect_their_blocks() {
        // Every embedded shader parses, and the passes with push constants show them.
        let mut with_push = 0;
        for v in VARIANTS {
            let b = block_sizes(v.spirv).unwrap();
            if let Some(&s) = b.get("push constants") {
                assert!(s > 0 && s <= 256, "{}: push constants {s} bytes", v.file);
                with_push += 1;
            }
        }
        assert!(with_push > 0);
    }
}
