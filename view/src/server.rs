//! The HTTP server: embedded assets, the JSON/binary API over the [`Session`], and a
//! server-sent event stream that tells pages when the rig was reloaded.
//!
//! API: `GET /api/scene` (scene, timeline, nodes, load errors), `GET /api/frame?f=N`
//! (binary frame, see [`crate::scene`]; header `X-Eval-Us`), `GET /api/errors`
//! (evaluation errors), `GET /api/node?name=N` (attributes), `POST /api/set` with
//! `{"plug": "n.a", "value": "RON text"}`, `GET /api/profile`,
//! `GET /api/graph?node=N&depth=D` (SVG), `GET /api/events` (SSE: `reload` events).

use std::io::{Read, Write};
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use tiny_http::{Header, Method, Request, Response, Server};

use crate::session::{Loader, ReloadTimes, Session};

/// Worker threads answering requests (event streams get a thread each).
const WORKERS: usize = 4;

/// How `sinew view` serves a rig.
pub struct ViewOptions {
    /// The rig file.
    pub rig: PathBuf,
    /// Address to listen on, e.g. `127.0.0.1:8484` (port 0: any free port).
    pub addr: String,
    /// How rig files are loaded.
    pub loader: Loader,
}

struct Shared {
    session: Mutex<Session>,
    /// The last reload: its revision and the event data the pages get.
    revision: Mutex<(u64, String)>,
    changed: Condvar,
}

/// What a reload did and where its time went, from the first file event on.
#[derive(Clone, Debug)]
pub struct ReloadReport {
    /// The rig file.
    pub rig: PathBuf,
    /// The session's revision after the reload.
    pub revision: u64,
    /// From the first file event to the start of the reload: the watcher's wait for a
    /// burst of events to settle (milliseconds).
    pub settle_ms: f64,
    /// The reload itself, by phase.
    pub times: ReloadTimes,
    /// When the first file event arrived, in milliseconds since the Unix epoch (pages
    /// and tests compare it with their own clocks).
    pub event_epoch_ms: f64,
}

impl std::fmt::Display for ReloadReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let t = &self.times;
        write!(
            f,
            "reloaded {} in {:.1} ms (settle {:.1}, load {:.1}, scene {:.1}, compile {:.1}){}",
            self.rig.display(),
            self.settle_ms + t.total_ms,
            self.settle_ms,
            t.load_ms,
            t.scene_ms,
            t.compile_ms,
            if t.ok { "" } else { " (errors shown in the page)" }
        )
    }
}

/// `t` in milliseconds since the Unix epoch.
fn epoch_ms(t: Instant) -> f64 {
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap_or_default();
    (now.as_secs_f64() - t.elapsed().as_secs_f64()) * 1e3
}

impl Shared {
    fn session(&self) -> MutexGuard<'_, Session> {
        self.session.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// A running viewer server.
pub struct Viewer {
    shared: Arc<Shared>,
    addr: SocketAddr,
    workers: Vec<std::thread::JoinHandle<()>>,
}

impl Viewer {
    /// Loads the rig (a rig that fails to load is served with its errors) and starts
    /// serving.
    pub fn start(opts: ViewOptions) -> Result<Viewer, String> {
        let listen_error = |e: &dyn std::fmt::Display| format!("cannot listen on {}: {e}", opts.addr);
        let listener = std::net::TcpListener::bind(&opts.addr).map_err(|e| listen_error(&e))?;
        // No Nagle delay: tiny_http writes a response's headers and body separately, and with
        // Nagle's algorithm the body's last segment waits for the client's delayed ACK, 40 ms
        // on Linux, per frame of playback on a kept-alive connection. Linux and the BSDs copy
        // TCP_NODELAY from the listening socket to the accepted ones.
        socket2::SockRef::from(&listener)
            .set_tcp_nodelay(true)
            .map_err(|e| listen_error(&e))?;
        let server = Server::from_listener(listener, None).map_err(|e| listen_error(&e))?;
        let addr = server
            .server_addr()
            .to_ip()
            .ok_or_else(|| format!("cannot listen on {}: not an IP address", opts.addr))?;
        let session = Session::new(&opts.rig, opts.loader);
        let revision = session.revision;
        let shared = Arc::new(Shared {
            session: Mutex::new(session),
            revision: Mutex::new((revision, String::new())),
            changed: Condvar::new(),
        });
        let server = Arc::new(server);
        let workers = (0..WORKERS)
            .map(|_| {
                let (server, shared) = (server.clone(), shared.clone());
                std::thread::spawn(move || {
                    while let Ok(request) = server.recv() {
                        handle(&shared, request);
                    }
                })
            })
            .collect();
        Ok(Viewer { shared, addr, workers })
    }

    /// The page's address.
    pub fn url(&self) -> String {
        format!("http://{}/", self.addr)
    }

    /// Loads the rig again and tells the pages. `event_at` is when the file event that
    /// asked for it arrived (the report measures from there).
    pub fn reload(&self, event_at: Instant) -> ReloadReport {
        let settle_ms = event_at.elapsed().as_secs_f64() * 1e3;
        let (times, revision, rig) = {
            let mut s = self.shared.session();
            let times = s.reload();
            (times, s.revision, s.path().to_path_buf())
        };
        let report = ReloadReport {
            rig,
            revision,
            settle_ms,
            times,
            event_epoch_ms: epoch_ms(event_at),
        };
        let data = serde_json::json!({
            "revision": revision, "ok": times.ok, "eventAt": report.event_epoch_ms,
            "reloadedAt": epoch_ms(Instant::now()), "settleMs": settle_ms, "loadMs": times.load_ms,
            "sceneMs": times.scene_ms, "compileMs": times.compile_ms,
        });
        *self.shared.revision.lock().unwrap_or_else(|p| p.into_inner()) = (revision, data.to_string());
        self.shared.changed.notify_all();
        report
    }

    /// The files the rig depends on (what to watch).
    pub fn files(&self) -> Vec<PathBuf> {
        self.shared.session().files()
    }

    /// Blocks while the server runs.
    pub fn wait(self) {
        for w in self.workers {
            let _ = w.join();
        }
    }
}

fn header(name: &str, value: &str) -> Header {
    Header::from_bytes(name.as_bytes(), value.as_bytes())
        .unwrap_or_else(|_| Header::from_bytes(&b"X-Invalid"[..], &b"1"[..]).expect("a valid constant header"))
}

fn json_response(v: &serde_json::Value, status: u16) -> Response<std::io::Cursor<Vec<u8>>> {
    Response::from_data(v.to_string().into_bytes())
        .with_status_code(status)
        .with_header(header("Content-Type", "application/json"))
        .with_header(header("Cache-Control", "no-store"))
}

/// Decodes `%XX` escapes and `+` in a query value.
fn decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'+' => out.push(b' '),
            b'%' if i + 2 < b.len() => {
                match u8::from_str_radix(std::str::from_utf8(&b[i + 1..i + 3]).unwrap_or("zz"), 16) {
                    Ok(v) => {
                        out.push(v);
                        i += 2;
                    }
                    Err(_) => out.push(b'%'),
                }
            }
            c => out.push(c),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

fn query(url: &str, key: &str) -> Option<String> {
    let q = url.split_once('?')?.1;
    q.split('&')
        .filter_map(|kv| kv.split_once('='))
        .find(|(k, _)| *k == key)
        .map(|(_, v)| decode(v))
}

fn handle(shared: &Arc<Shared>, mut request: Request) {
    let url = request.url().to_string();
    let path = url.split('?').next().unwrap_or("/").to_string();
    let err = |m: String, status: u16| json_response(&serde_json::json!({ "error": m }), status);
    let response = match (request.method(), path.as_str()) {
        (Method::Get, "/api/events") => {
            let shared = shared.clone();
            std::thread::spawn(move || event_stream(&shared, request));
            return;
        }
        (Method::Get, "/api/scene") => json_response(&shared.session().scene_json(), 200),
        (Method::Get, "/api/errors") => json_response(&shared.session().eval_errors_json(), 200),
        (Method::Get, "/api/frame") => {
            let frame = query(&url, "f")
                .and_then(|f| f.parse::<f64>().ok())
                .filter(|f| f.is_finite());
            let Some(frame) = frame else {
                let _ = request.respond(err("give the frame: /api/frame?f=12".into(), 400));
                return;
            };
            let mut bytes = Vec::new();
            let (us, errors, revision) = {
                let mut s = shared.session();
                let us = s.frame(frame, &mut bytes);
                (us, s.eval_errors_json(), s.revision)
            };
            match us {
                Some(us) => Response::from_data(bytes)
                    .with_header(header("Content-Type", "application/octet-stream"))
                    .with_header(header("Cache-Control", "no-store"))
                    .with_header(header("X-Eval-Us", &format!("{us:.1}")))
                    .with_header(header("X-Revision", &revision.to_string()))
                    .with_header(header(
                        "X-Eval-Errors",
                        &errors.as_array().map(|a| a.len()).unwrap_or(0).to_string(),
                    )),
                None => err("no rig loaded".into(), 409),
            }
        }
        (Method::Get, "/api/node") => match query(&url, "name") {
            Some(name) => match shared.session().node_json(&name) {
                Ok(v) => json_response(&v, 200),
                Err(e) => err(e, 404),
            },
            None => err("give the node: /api/node?name=NODE".into(), 400),
        },
        (Method::Post, "/api/set") => {
            let mut body = String::new();
            let parsed = request
                .as_reader()
                .take(1 << 20)
                .read_to_string(&mut body)
                .map_err(|e| e.to_string())
                .and_then(|_| serde_json::from_str::<serde_json::Value>(&body).map_err(|e| e.to_string()));
            match parsed {
                Ok(v) => {
                    let plug = v["plug"].as_str().unwrap_or_default();
                    let value = match &v["value"] {
                        serde_json::Value::String(s) => s.clone(),
                        other => other.to_string(),
                    };
                    match shared.session().set(plug, &value) {
                        Ok(r) => json_response(&r, 200),
                        Err(e) => err(e, 400),
                    }
                }
                Err(e) => err(format!("bad request body: {e}"), 400),
            }
        }
        (Method::Get, "/api/profile") => match shared.session().profile(None) {
            Ok(v) => json_response(&v, 200),
            Err(e) => err(e, 400),
        },
        (Method::Get, "/api/graph") => {
            let node = query(&url, "node").unwrap_or_default();
            let depth = query(&url, "depth")
                .and_then(|d| d.parse().ok())
                .unwrap_or(2usize)
                .min(6);
            match shared.session().graph_svg(&node, depth) {
                Ok(svg) => Response::from_data(svg.into_bytes()).with_header(header("Content-Type", "image/svg+xml")),
                Err(e) => err(e, 404),
            }
        }
        (Method::Get, p) => match crate::assets::get(p) {
            Some((bytes, ty)) => Response::from_data(bytes.to_vec()).with_header(header("Content-Type", ty)),
            None => err(format!("not found: {p}"), 404),
        },
        _ => err("method not allowed".into(), 405),
    };
    let _ = request.respond(response);
}

/// Server-sent events: a `reload` event whenever the rig is reloaded, its data the
/// reload's JSON (revision, `ok`, the file event's time in epoch milliseconds and the
/// phases' times), and a comment every 15 s to keep the connection open.
fn event_stream(shared: &Arc<Shared>, request: Request) {
    let mut w = request.into_writer();
    let head = "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\nConnection: keep-alive\r\n\r\n";
    let mut seen = shared.revision.lock().unwrap_or_else(|p| p.into_inner()).0;
    if w.write_all(head.as_bytes())
        .and_then(|_| w.write_all(b": connected\n\n"))
        .and_then(|_| w.flush())
        .is_err()
    {
        return;
    }
    loop {
        let (rev, data) = {
            let guard = shared.revision.lock().unwrap_or_else(|p| p.into_inner());
            let (guard, _) = shared
                .changed
                .wait_timeout_while(guard, Duration::from_secs(15), |r| r.0 == seen)
                .unwrap_or_else(|p| p.into_inner());
            guard.clone()
        };
        let msg = if rev != seen {
            seen = rev;
            format!("event: reload\ndata: {data}\n\n")
        } else {
            ": ping\n\n".to_string()
        };
        if w.write_all(msg.as_bytes()).and_then(|_| w.flush()).is_err() {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn query_values_are_decoded() {
        assert_eq!(
            query("/api/node?name=arm%5BL%5D&x=1", "name").as_deref(),
            Some("arm[L]")
        );
        assert_eq!(query("/api/frame?f=12.5", "f").as_deref(), Some("12.5"));
        assert_eq!(query("/api/frame", "f"), None);
        assert_eq!(decode("a+b%2"), "a b%2");
    }
}
