//! An OBJ mesh (an environment's `<Geom type="trimesh">`) from raw bytes: parsed (vertex and
//! face counts, indices out of range, NaN), and when accepted, its bounds and its reading
//! as a height map (the load check every world makes).
#![no_main]

use libfuzzer_sys::fuzz_target;
use proleg::config::mesh::parse_obj;

fuzz_target!(|data: &[u8]| {
    let Some(text) = proleg_fuzz::text(data) else {
        return;
    };
    if let Ok(mesh) = parse_obj(std::path::Path::new("fuzz.obj"), text) {
        std::hint::black_box((mesh.bounds(), mesh.height_map().is_ok()));
    }
});
