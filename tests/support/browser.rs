//! Shared by the browser tests (tests/view_browser*.rs): starting `sinew view` on a free
//! port, a WebDriver session on chromedriver driving headless Chromium, screenshots.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

pub const SINEW: &str = env!("CARGO_BIN_EXE_sinew");

/// The `sinew` the viewer tests serve with: `SINEW_VIEW_BIN` when set (e.g. a release build,
/// to measure rates), else the binary cargo built for the tests.
pub fn view_bin() -> String {
    std::env::var("SINEW_VIEW_BIN").unwrap_or_else(|_| SINEW.to_string())
}
pub const WIDTH: u32 = 1100;
pub const HEIGHT: u32 = 680;

/// Now, in milliseconds since the Unix epoch (the page and the server use the same clock).
pub fn epoch_ms() -> f64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_secs_f64()
        * 1e3
}

/// Chromium and chromedriver from PATH, or `None` after printing why `test` is skipped.
pub fn chromium(test: &str) -> Option<(PathBuf, PathBuf)> {
    match (
        find(&["chromium", "chromium-browser", "google-chrome"]),
        find(&["chromedriver"]),
    ) {
        (Some(c), Some(d)) => Some((c, d)),
        _ => {
            eprintln!(
                "SKIPPED {test}: no chromium and chromedriver on PATH (apt-get install chromium chromium-driver)"
            );
            None
        }
    }
}

/// Kills a child process when dropped.
pub struct Proc(Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

pub fn find(names: &[&str]) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    names
        .iter()
        .flat_map(|n| std::env::split_paths(&path).map(move |d| d.join(n)))
        .find(|p| p.is_file())
}

pub fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// A WebDriver session on chromedriver.
pub struct Browser {
    base: String,
    _driver: Proc,
    _profile: PathBuf,
}

impl Drop for Browser {
    /// Ends the WebDriver session, which closes Chromium: killing chromedriver alone (its
    /// `Proc` is dropped after this) left every test's browser processes running.
    fn drop(&mut self) {
        let _ = ureq::delete(&self.base).timeout(Duration::from_secs(10)).call();
    }
}

impl Browser {
    pub fn start(chromium: &Path, chromedriver: &Path, dir: &Path) -> Browser {
        let port = free_port();
        let driver = Proc(
            Command::new(chromedriver)
                .arg(format!("--port={port}"))
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .expect("start chromedriver"),
        );
        let root = format!("http://127.0.0.1:{port}");
        let profile = dir.join("chromium-profile");
        let caps = json!({ "capabilities": { "alwaysMatch": { "browserName": "chrome",
        "goog:chromeOptions": { "binary": chromium.to_string_lossy(), "args": [
            "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync",
            "--enable-unsafe-swiftshader", "--use-angle=swiftshader", "--hide-scrollbars",
            format!("--user-data-dir={}", profile.display()),
            format!("--window-size={WIDTH},{HEIGHT}"),
        ]}}}});
        let started = Instant::now();
        let session = loop {
            match ureq::post(&format!("{root}/session")).send_string(&caps.to_string()) {
                Ok(r) => break r.into_string().unwrap(),
                Err(e) if started.elapsed() < Duration::from_secs(20) => {
                    let _ = e;
                    std::thread::sleep(Duration::from_millis(100));
                }
                Err(e) => panic!("chromedriver did not start a session: {e}"),
            }
        };
        let session: Value = serde_json::from_str(&session).unwrap();
        let id = session["value"]["sessionId"]
            .as_str()
            .expect("a session id")
            .to_string();
        Browser {
            base: format!("{root}/session/{id}"),
            _driver: driver,
            _profile: profile,
        }
    }

    pub fn post(&self, what: &str, body: Value) -> Value {
        let r = ureq::post(&format!("{}/{what}", self.base))
            .send_string(&body.to_string())
            .unwrap_or_else(|e| panic!("WebDriver {what}: {}", err_body(e)));
        serde_json::from_str::<Value>(&r.into_string().unwrap()).unwrap()["value"].take()
    }

    pub fn go(&self, url: &str) {
        self.post("url", json!({ "url": url }));
    }

    /// Runs `body` as an async function in the page and returns its result.
    pub fn js(&self, body: &str) -> Value {
        self.post(
            "execute/sync",
            json!({ "script": format!("return (async () => {{ {body} }})();"), "args": [] }),
        )
    }

    /// Waits until `cond` (a JS expression) is truthy.
    pub fn wait(&self, cond: &str, what: &str) {
        let started = Instant::now();
        while started.elapsed() < Duration::from_secs(30) {
            if self.js(&format!("return !!({cond});")) == json!(true) {
                return;
            }
            std::thread::sleep(Duration::from_millis(25));
        }
        panic!(
            "timed out waiting for {what} ({cond}); page errors: {}",
            self.js("return window.__errors;")
        );
    }

    /// Clicks the first element matching the CSS selector `css` as a user would (WebDriver
    /// scrolls it into view and clicks its centre).
    pub fn click(&self, css: &str) {
        let found = self.post("element", json!({ "using": "css selector", "value": css }));
        let id = found
            .as_object()
            .and_then(|o| o.values().next())
            .and_then(Value::as_str)
            .unwrap_or_else(|| panic!("no element {css}: {found}"))
            .to_string();
        self.post(&format!("element/{id}/click"), json!({}));
    }

    /// A mouse click at (`x`, `y`) CSS pixels of the viewport (WebDriver pointer actions:
    /// the page gets real pointerdown/pointerup events there).
    pub fn click_at(&self, x: f64, y: f64) {
        let (x, y) = (x.round() as i64, y.round() as i64);
        self.post(
            "actions",
            json!({ "actions": [{ "type": "pointer", "id": "mouse", "parameters": { "pointerType": "mouse" },
                "actions": [
                    { "type": "pointerMove", "duration": 0, "x": x, "y": y, "origin": "viewport" },
                    { "type": "pointerDown", "button": 0 },
                    { "type": "pointerUp", "button": 0 },
                ] }] }),
        );
    }

    /// The bounding box of the first element matching `css`: (x, y, width, height).
    pub fn rect(&self, css: &str) -> [f64; 4] {
        let v = self.js(&format!(
            "const r = document.querySelector({css:?}).getBoundingClientRect(); return [r.x, r.y, r.width, r.height];"
        ));
        let n: Vec<f64> = v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
        [n[0], n[1], n[2], n[3]]
    }

    pub fn screenshot(&self) -> (Vec<u8>, image::Rgba) {
        use base64::Engine;
        let r = ureq::get(&format!("{}/screenshot", self.base)).call().unwrap();
        let v: Value = serde_json::from_str(&r.into_string().unwrap()).unwrap();
        let png = base64::engine::general_purpose::STANDARD
            .decode(v["value"].as_str().unwrap())
            .unwrap();
        let img = image::decode(&png);
        (png, img)
    }
}

pub fn err_body(e: ureq::Error) -> String {
    match e {
        ureq::Error::Status(code, r) => format!("status {code}: {}", r.into_string().unwrap_or_default()),
        other => other.to_string(),
    }
}

/// Decoded screenshots.
pub mod image {
    /// RGBA pixels, row by row.
    pub struct Rgba {
        pub width: usize,
        pub height: usize,
        pub data: Vec<u8>,
    }

    pub fn decode(png: &[u8]) -> Rgba {
        let mut dec = png::Decoder::new(png);
        dec.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
        let mut reader = dec.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        let channels = info.color_type.samples();
        let data = buf[..info.buffer_size()]
            .chunks(channels)
            .flat_map(|p| {
                if channels >= 3 {
                    [p[0], p[1], p[2], 255]
                } else {
                    [p[0], p[0], p[0], 255]
                }
            })
            .collect();
        Rgba {
            width: info.width as usize,
            height: info.height as usize,
            data,
        }
    }
}

/// `sinew view RIG --port 0`: the process and the page's address.
pub fn serve(rig: &Path) -> (Proc, String) {
    let mut child = Command::new(view_bin())
        .args(["view", rig.to_str().unwrap(), "--port", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("start sinew view");
    let mut line = String::new();
    let mut out = BufReader::new(child.stdout.take().unwrap());
    out.read_line(&mut line).unwrap();
    // Keep reading (reload messages) so the server never writes to a closed pipe.
    std::thread::spawn(move || {
        let mut l = String::new();
        while out.read_line(&mut l).is_ok_and(|n| n > 0) {
            eprint!("sinew view: {l}");
            l.clear();
        }
    });
    let url = line
        .split_whitespace()
        .find(|w| w.starts_with("http://"))
        .unwrap_or_else(|| panic!("no address in {line:?}"))
        .to_string();
    (Proc(child), url)
}

/// Writes a screenshot into docs/images/ when `SINEW_UPDATE_SCREENSHOTS` is set.
pub fn save_screenshot(png: &[u8], name: &str) {
    if std::env::var_os("SINEW_UPDATE_SCREENSHOTS").is_some() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/images");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join(name), png).unwrap();
    }
}
