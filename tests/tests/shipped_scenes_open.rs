//! Every scene file shipped in `scenes/` opens through the front door a host and `hairsys
//! simulate` use (`Session::from_scene`: the scene built, its colliders inserted, its guide
//! blends bound to the strands) and steps a frame. Regression: Sintel's scene built, but the
//! session panicked binding the blends of sim hairs the build had left out.

use std::path::PathBuf;

use hairsys::scene::SceneFile;
use hairsys::Session;

#[test]
fn every_shipped_scene_opens_as_a_session_and_steps() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let mut names: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    names.sort();
    assert!(names.len() >= 7, "{names:?}");
    for path in names {
        let scene = SceneFile::load(&path).unwrap();
        let mut session =
            Session::from_scene(&scene).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let report = session
            .step()
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(report.max_stretch.is_finite(), "{}", path.display());
        println!("{}: {} strands", path.display(), session.strands().len());
    }
}
