#![no_main]
//! The .obj importer: `vgeo::mesh::load_bytes(data, Format::Obj, ..)`; see `vgeo_fuzz::import`.

use libfuzzer_sys::fuzz_target;
use vgeo::mesh::Format;

fuzz_target!(|data: &[u8]| {
    vgeo_fuzz::import(Format::Obj, "fuzz.obj", data);
});
