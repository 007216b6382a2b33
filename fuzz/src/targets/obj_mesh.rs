//! An OBJ mesh (an environment's `<Geom type="trimesh">`) from raw bytes: parsed (vertex and
//! face counts, indices out of range, NaN), and when accepted, its bounds and its reading
//! as a height map (the load check every world makes).

use proleg::config::mesh::parse_obj;

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    let Some(text) = crate::text(data) else {
        return;
    };
    if let Ok(mesh) = parse_obj(std::path::Path::new("fuzz.obj"), text) {
        std::hint::black_box((mesh.bounds(), mesh.height_map().is_ok()));
    }
}
