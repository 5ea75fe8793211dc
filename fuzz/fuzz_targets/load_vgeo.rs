#![no_main]
//! The `.vgeo` loader: `vgeo::format::load`; see `vgeo_fuzz::load_vgeo`.

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    vgeo_fuzz::load_vgeo(data);
});
