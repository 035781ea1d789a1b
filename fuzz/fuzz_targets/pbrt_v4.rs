//! Fuzzes the pbrt-v4 loader: any bytes must give a scene or an error,
//! never a panic or a hang. The input is written to a scene file in a
//! per-process directory (the loader reads files: includes, meshes), and a
//! successfully loaded description is also built, as `lqmc render` would.
#![no_main]

use libfuzzer_sys::fuzz_target;
use render::scene::Scene;
use render::scene::loader::{LoadOptions, load_scene_file};

fuzz_target!(|data: &[u8]| {
    let directory = std::env::temp_dir().join(format!("lqmc-fuzz-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&directory);
    let path = directory.join("scene.pbrt");
    if std::fs::write(&path, data).is_err() {
        return;
    }
    if let Ok(loaded) = load_scene_file(&path, &LoadOptions::default()) {
        let mut description = loaded.description;
        // Keep the build cheap: the camera's resolution does not matter here.
        description.camera.resolution = [4, 4];
        let _ = Scene::build(&description);
    }
});
