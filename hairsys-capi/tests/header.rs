//! `include/hairsys.h` is what cbindgen makes of the source today: the test regenerates it in
//! memory and compares. `UPDATE_HEADER=1` writes the regenerated header instead.

use std::path::Path;

#[test]
fn the_checked_in_header_is_what_cbindgen_generates() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml"))
        .expect("cbindgen.toml is readable and valid");
    let bindings = cbindgen::Builder::new()
        .with_crate(dir)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header from src/");
    let mut generated = Vec::new();
    bindings.write(&mut generated);
    let path = dir.join("include/hairsys.h");
    if std::env::var_os("UPDATE_HEADER").is_some() {
        std::fs::write(&path, &generated).expect("include/hairsys.h is writable");
        return;
    }
    let checked_in = std::fs::read(&path).unwrap_or_default();
    assert!(
        checked_in == generated,
        "hairsys-capi/include/hairsys.h is out of date with src/: regenerate it with\n    \
         UPDATE_HEADER=1 cargo test -p hairsys-capi --test header\nand commit it"
    );
}
