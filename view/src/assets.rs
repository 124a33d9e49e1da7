//! The page's files, embedded in the binary: the viewer's own HTML, CSS and JavaScript,
//! and three.js r170 vendored from the npm package `three@0.170.0` (MIT; see
//! `assets/vendor/three/`).

/// The embedded file served at `path`, with its content type.
pub fn get(path: &str) -> Option<(&'static [u8], &'static str)> {
    const JS: &str = "text/javascript; charset=utf-8";
    Some(match path {
        "/" | "/index.html" => (include_bytes!("../assets/index.html"), "text/html; charset=utf-8"),
        "/style.css" => (include_bytes!("../assets/style.css"), "text/css; charset=utf-8"),
        "/app.js" => (include_bytes!("../assets/app.js"), JS),
        "/panels.js" => (include_bytes!("../assets/panels.js"), JS),
        "/draw.js" => (include_bytes!("../assets/draw.js"), JS),
        "/vendor/three/three.module.min.js" => (include_bytes!("../assets/vendor/three/three.module.min.js"), JS),
        "/vendor/three/OrbitControls.js" => (include_bytes!("../assets/vendor/three/OrbitControls.js"), JS),
        "/vendor/three/LICENSE" => (
            include_bytes!("../assets/vendor/three/LICENSE"),
            "text/plain; charset=utf-8",
        ),
        _ => return None,
    })
}
