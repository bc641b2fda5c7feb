//! The preview's HTTP server: loopback only, every request checked for the session's token and
//! for a loopback Host (against DNS rebinding), a fixed set of routes that never reach the file
//! system, and server-sent events that tell the open pages when the scene changed.
//!
//! tiny_http: a small, synchronous, well-kept server crate. The preview serves one user's few
//! tabs on loopback, so a thread per event stream and one loop for the rest are plenty, and
//! raycast needs no async runtime.

use std::io::{Read, Write};
use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{RecvTimeoutError, Sender, channel};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tiny_http::{Header, Method, Request, Response, Server};

use crate::job::Options;
use crate::render::RenderCounter;

/// The page and its script, built into the binary.
const INDEX_HTML: &str = include_str!("page/index.html");
const PREVIEW_JS: &str = include_str!("page/preview.js");

/// How often an idle event stream sends a comment, so that a closed tab's thread ends.
const KEEP_ALIVE: Duration = Duration::from_secs(10);

/// What the server shows: the current drawing (or the error that replaced the last good one).
#[derive(Debug, Default)]
pub struct Shown {
    /// Counts the scenes shown; each page asks for the one it is told of.
    pub version: u64,
    /// The drawing's description for the page, as JSON.
    pub meta: String,
    /// The drawing's vertices.
    pub vertices: Arc<Vec<u8>>,
    /// The scene's error, as the command line prints it, while the file does not read.
    pub error: Option<String>,
    /// The page's camera, in the scene file's syntax, once a page has moved it.
    pub camera: Option<String>,
}

/// A running preview server.
pub struct PreviewServer {
    server: Arc<Server>,
    /// The command line: what 'r' renders and 't' traces.
    options: Options,
    /// The progress of 'r''s render, which the pages are told of while it runs.
    progress: &'static RenderCounter,
    token: String,
    /// The cookie the page keeps the token in: named for the port, as cookies are shared by
    /// every port of a host.
    cookie: String,
    shown: Arc<Mutex<Shown>>,
    streams: Arc<Mutex<Vec<Sender<String>>>>,
    quit: Arc<AtomicBool>,
}

impl PreviewServer {
    /// Binds 127.0.0.1:`port` (0: any free port).
    pub fn bind(
        port: u16,
        token: String,
        shown: Shown,
        options: &Options,
    ) -> Result<PreviewServer, String> {
        let server = Server::http(("127.0.0.1", port))
            .map_err(|e| format!("cannot serve the preview on 127.0.0.1:{port}: {e}"))?;
        let port = server.server_addr().to_ip().map_or(port, |a| a.port());
        Ok(PreviewServer {
            server: Arc::new(server),
            options: options.clone(),
            // One a server, for as long as the process runs.
            progress: Box::leak(Box::default()),
            token,
            cookie: format!("raycast_token_{port}"),
            shown: Arc::new(Mutex::new(shown)),
            streams: Arc::new(Mutex::new(Vec::new())),
            quit: Arc::new(AtomicBool::new(false)),
        })
    }

    /// The address it listens on.
    pub fn address(&self) -> SocketAddr {
        self.server
            .server_addr()
            .to_ip()
            .expect("bound to an IP address")
    }

    /// The address to open, token included.
    pub fn url(&self) -> String {
        format!("http://{}/?token={}", self.address(), self.token)
    }

    /// The flag that ends [`PreviewServer::run`] (the page's 'q', or Ctrl-C).
    pub fn quit_flag(&self) -> Arc<AtomicBool> {
        self.quit.clone()
    }

    /// What it shows, for the watcher to replace.
    pub fn shown(&self) -> Arc<Mutex<Shown>> {
        self.shown.clone()
    }

    /// Tells every open page `event` (a server-sent event's name) with `data` (one line).
    pub fn announce(&self, event: &str, data: &str) {
        announce(&self.streams, event, data);
    }

    /// A handle that announces from another thread.
    pub fn announcer(&self) -> Announcer {
        Announcer {
            streams: self.streams.clone(),
        }
    }

    /// Answers requests until the quit flag is raised.
    pub fn run(&self) {
        while !self.quit.load(Ordering::SeqCst) {
            match self.server.recv_timeout(Duration::from_millis(50)) {
                Ok(Some(request)) => self.answer(request),
                Ok(None) => {}
                Err(_) => break,
            }
        }
        // Ends the event streams, so that their threads let go.
        self.streams.lock().map(|mut s| s.clear()).ok();
        self.server.unblock();
    }

    fn answer(&self, mut request: Request) {
        if let Err(refusal) = self.admit(&request) {
            respond(request, text(403, &refusal));
            return;
        }
        let url = request.url().to_string();
        let path = url.split('?').next().unwrap_or("");
        let method = request.method().clone();
        let response = match (&method, path) {
            (Method::Get, "/") => html(INDEX_HTML).with_header(header(
                "Set-Cookie",
                &format!(
                    "{}={}; Path=/; HttpOnly; SameSite=Strict",
                    self.cookie, self.token
                ),
            )),
            (Method::Get, "/preview.js") => typed(
                200,
                PREVIEW_JS.as_bytes().to_vec(),
                "text/javascript; charset=utf-8",
            ),
            (Method::Get, "/api/scene") => {
                let shown = self.shown.lock().expect("not poisoned");
                let body = format!(
                    "{{\"version\":{},\"error\":{},\"scene\":{}}}",
                    shown.version,
                    serde_json::to_string(&shown.error).unwrap_or_default(),
                    if shown.meta.is_empty() {
                        "null"
                    } else {
                        &shown.meta
                    }
                );
                typed(200, body.into_bytes(), "application/json")
            }
            (Method::Get, "/api/geometry") => {
                let vertices = self.shown.lock().expect("not poisoned").vertices.clone();
                typed(200, vertices.to_vec(), "application/octet-stream")
            }
            (Method::Get, "/api/camera") => {
                match &self.shown.lock().expect("not poisoned").camera {
                    Some(camera) => typed(
                        200,
                        camera.clone().into_bytes(),
                        "text/plain; charset=utf-8",
                    ),
                    None => text(404, "no page has reported its camera yet"),
                }
            }
            (Method::Post, "/api/camera") => {
                let mut body = String::new();
                let read = request
                    .as_reader()
                    .take(64 * 1024)
                    .read_to_string(&mut body);
                match read {
                    // Empty: the page is at the file's camera again.
                    Ok(_) if body.trim().is_empty() => {
                        self.shown.lock().expect("not poisoned").camera = None;
                        text(204, "")
                    }
                    Ok(_) if looks_like_a_camera(&body) => {
                        self.shown.lock().expect("not poisoned").camera = Some(body);
                        text(204, "")
                    }
                    _ => text(400, "expected a camera in the scene file's syntax"),
                }
            }
            (Method::Post, "/api/render") => {
                self.render(request);
                return;
            }
            (Method::Get, "/api/raytree") => self.ray_tree(&url),
            (Method::Get, "/api/grid") => match super::view::grid(&self.options) {
                Ok(grid) => typed(200, grid.to_string().into_bytes(), "application/json"),
                Err(error) => text(500, &error.to_string()),
            },
            (Method::Get, "/api/gridwalk") => self.grid_walk(&url),
            (Method::Post, "/api/quit") => {
                self.quit.store(true, Ordering::SeqCst);
                text(204, "")
            }
            // Browsers ask for it by themselves; there is none.
            (Method::Get, "/favicon.ico") => text(204, ""),
            (Method::Get, "/api/events") => {
                self.stream(request);
                return;
            }
            (_, "/" | "/preview.js" | "/api/scene" | "/api/geometry" | "/api/camera")
            | (_, "/api/quit" | "/api/events" | "/api/render" | "/api/raytree")
            | (_, "/api/grid" | "/api/gridwalk") => text(405, "method not allowed"),
            _ => text(404, "not found"),
        };
        respond(request, response);
    }

    /// The page's camera, in the scene file's syntax, once it has moved it from the file's.
    fn camera(&self) -> Option<String> {
        self.shown.lock().expect("not poisoned").camera.clone()
    }

    /// 'r': renders the page's view and writes the line's images, on a thread of its own (a
    /// long render keeps the other requests waiting for nothing); answers with the first
    /// picture as PNG.
    fn render(&self, request: Request) {
        let options = self.options.clone();
        let camera = self.camera();
        let (progress, announcer) = (self.progress, self.announcer());
        std::thread::spawn(move || {
            // The pages hear how far the render is, five times a second, until it is done.
            let rendering = Arc::new(AtomicBool::new(true));
            let watching = rendering.clone();
            let reporter = std::thread::spawn(move || {
                while watching.load(Ordering::SeqCst) {
                    std::thread::sleep(Duration::from_millis(200));
                    let percent = (100.0 * progress.fraction()).floor();
                    announcer.announce("progress", &format!("{percent}"));
                }
            });
            let result = super::view::render_view(&options, camera.as_deref(), Some(progress));
            rendering.store(false, Ordering::SeqCst);
            let _ = reporter.join();
            let answer = match result {
                Ok(rendered) => {
                    let stats = serde_json::to_string(&rendered.stats).unwrap_or_default();
                    typed(200, rendered.png, "image/png")
                        .with_header(header(
                            "X-Render-Seconds",
                            &format!("{:.3}", rendered.seconds),
                        ))
                        // JSON: one line, the block's newlines escaped.
                        .with_header(header("X-Render-Stats", &stats))
                }
                Err(error) => text(500, &error.to_string()),
            };
            respond(request, answer);
        });
    }

    /// 't' and `GET /api/raytree?x=X&y=Y[&format=text]`: the pixel's ray tree for the page's
    /// view, as `-inspect X Y -json` (or without `-json`) prints it.
    fn ray_tree(&self, url: &str) -> Answer {
        let query = url.split_once('?').map_or("", |(_, q)| q);
        let value = |name: &str| {
            query
                .split('&')
                .find_map(|pair| pair.strip_prefix(&format!("{name}=")))
        };
        let pixel = |name: &str| value(name).and_then(|v| v.parse::<u32>().ok());
        let (Some(x), Some(y)) = (pixel("x"), pixel("y")) else {
            return text(
                400,
                "expected ?x=X&y=Y, pixel coordinates as -inspect counts them",
            );
        };
        let as_text = value("format") == Some("text");
        let camera = self.camera();
        match super::view::ray_tree(&self.options, camera.as_deref(), (x, y), as_text) {
            Ok(body) if as_text => typed(200, body.into_bytes(), "text/plain; charset=utf-8"),
            Ok(body) => typed(200, body.into_bytes(), "application/json"),
            Err(error) => text(400, &error.to_string()),
        }
    }

    /// 'g' after 't': `GET /api/gridwalk?x=X&y=Y`, the grid cells the pixel's tree walks.
    fn grid_walk(&self, url: &str) -> Answer {
        let Some(pixel) = pixel_of(url) else {
            return text(
                400,
                "expected ?x=X&y=Y, pixel coordinates as -inspect counts them",
            );
        };
        if pixel.0 >= self.options.width || pixel.1 >= self.options.height {
            return text(400, "the pixel is outside the image");
        }
        let camera = self.camera();
        match super::view::grid_walk(&self.options, camera.as_deref(), pixel) {
            Ok(walk) => typed(200, walk.to_string().into_bytes(), "application/json"),
            Err(error) => text(400, &error.to_string()),
        }
    }

    /// Refuses a request whose Host is not a loopback name (a page elsewhere that renamed
    /// itself to 127.0.0.1) or that carries no token.
    fn admit(&self, request: &Request) -> Result<(), String> {
        let host = header_value(request, "Host").unwrap_or_default();
        if !is_loopback_host(&host) {
            return Err(format!(
                "refused: Host '{host}' is not 127.0.0.1, [::1] or localhost"
            ));
        }
        let from_query = request
            .url()
            .split_once('?')
            .and_then(|(_, query)| {
                query
                    .split('&')
                    .find_map(|pair| pair.strip_prefix("token="))
            })
            .map(str::to_string);
        let from_cookie = header_value(request, "Cookie").and_then(|cookies| {
            cookies.split(';').find_map(|c| {
                c.trim()
                    .strip_prefix(&format!("{}=", self.cookie))
                    .map(str::to_string)
            })
        });
        let matches = |t: &Option<String>| t.as_deref().is_some_and(|t| same(t, &self.token));
        if matches(&from_query) || matches(&from_cookie) {
            Ok(())
        } else {
            Err("refused: open the address raycast printed, with its ?token=".into())
        }
    }

    /// A server-sent event stream, on a thread of its own until the page goes away. Written
    /// straight to the connection, each event flushed as it comes (tiny_http's own responses
    /// buffer their chunks).
    fn stream(&self, request: Request) {
        let (send, receive) = channel::<String>();
        let version = self.shown.lock().expect("not poisoned").version;
        send.send(format!("event: scene\ndata: {version}\n\n")).ok();
        self.streams.lock().expect("not poisoned").push(send);
        std::thread::spawn(move || {
            let mut out = request.into_writer();
            let head = "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\n\
                        Cache-Control: no-store\r\nConnection: close\r\n\r\n";
            if out
                .write_all(head.as_bytes())
                .and_then(|()| out.flush())
                .is_err()
            {
                return;
            }
            loop {
                let message = match receive.recv_timeout(KEEP_ALIVE) {
                    Ok(message) => message,
                    // A comment: its failed write ends the stream of a closed tab.
                    Err(RecvTimeoutError::Timeout) => ": still here\n\n".to_string(),
                    Err(RecvTimeoutError::Disconnected) => return,
                };
                if out
                    .write_all(message.as_bytes())
                    .and_then(|()| out.flush())
                    .is_err()
                {
                    return;
                }
            }
        });
    }
}

/// Tells the open pages of a server about changes, from any thread.
#[derive(Clone)]
pub struct Announcer {
    streams: Arc<Mutex<Vec<Sender<String>>>>,
}

impl Announcer {
    /// [`PreviewServer::announce`].
    pub fn announce(&self, event: &str, data: &str) {
        announce(&self.streams, event, data);
    }
}

fn announce(streams: &Mutex<Vec<Sender<String>>>, event: &str, data: &str) {
    let message = format!(
        "event: {event}\ndata: {}\n\n",
        data.replace('\n', "\ndata: ")
    );
    if let Ok(mut streams) = streams.lock() {
        streams.retain(|s| s.send(message.clone()).is_ok());
    }
}

/// The value of `name` in the URL's query.
fn query_value<'u>(url: &'u str, name: &str) -> Option<&'u str> {
    let query = url.split_once('?').map_or("", |(_, q)| q);
    query.split('&').find_map(|pair| {
        pair.strip_prefix(name)
            .and_then(|rest| rest.strip_prefix('='))
    })
}

/// The pixel a request names: `?x=X&y=Y`.
fn pixel_of(url: &str) -> Option<(u32, u32)> {
    let number = |name: &str| query_value(url, name).and_then(|v| v.parse::<u32>().ok());
    Some((number("x")?, number("y")?))
}

/// Whether `host` (a Host header: name and port) names this machine's loopback.
pub fn is_loopback_host(host: &str) -> bool {
    let name = if let Some(rest) = host.strip_prefix('[') {
        match rest.split_once(']') {
            Some((name, port)) if port.is_empty() || is_port(port) => name,
            _ => return false,
        }
    } else {
        match host.rsplit_once(':') {
            Some((name, port)) if is_port(port) => name,
            Some(_) => return false,
            None => host,
        }
    };
    matches!(
        name.to_ascii_lowercase().as_str(),
        "127.0.0.1" | "::1" | "localhost"
    )
}

fn is_port(port: &str) -> bool {
    port.strip_prefix(':')
        .unwrap_or(port)
        .parse::<u16>()
        .is_ok()
}

/// Compares two tokens in time that depends only on their lengths.
fn same(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).fold(0, |d, (x, y)| d | (x ^ y)) == 0
}

/// Whether a page's camera report is a camera block of the scene file's syntax (it is only
/// stored and shown, never read as a scene, but a bad page should not fill it with anything).
fn looks_like_a_camera(body: &str) -> bool {
    let body = body.trim_start();
    (body.starts_with("OrthographicCamera {") || body.starts_with("PerspectiveCamera {"))
        && body.trim_end().ends_with('}')
        && body
            .chars()
            .all(|c| !c.is_control() || c == '\n' || c == ' ')
}

fn header_value(request: &Request, name: &'static str) -> Option<String> {
    request
        .headers()
        .iter()
        .find(|h| h.field.equiv(name))
        .map(|h| h.value.as_str().to_string())
}

fn header(name: &str, value: &str) -> Header {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("a valid header")
}

type Answer = Response<std::io::Cursor<Vec<u8>>>;

fn typed(status: u16, body: Vec<u8>, content_type: &str) -> Answer {
    Response::from_data(body)
        .with_status_code(status)
        .with_header(header("Content-Type", content_type))
        .with_header(header("Cache-Control", "no-store"))
        .with_header(header("X-Content-Type-Options", "nosniff"))
}

fn text(status: u16, body: &str) -> Answer {
    typed(
        status,
        body.as_bytes().to_vec(),
        "text/plain; charset=utf-8",
    )
}

fn html(body: &str) -> Answer {
    typed(200, body.as_bytes().to_vec(), "text/html; charset=utf-8")
}

fn respond(request: Request, response: Answer) {
    // A page that went away before its answer: nothing to do.
    let _ = request.respond(response);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loopback_hosts() {
        for host in [
            "127.0.0.1",
            "127.0.0.1:8080",
            "localhost:1",
            "LOCALHOST",
            "[::1]",
            "[::1]:9000",
        ] {
            assert!(is_loopback_host(host), "{host}");
        }
        for host in [
            "",
            "evil.example",
            "evil.example:80",
            "127.0.0.1.evil.example",
            "localhost.evil.example:8080",
            "[::2]:80",
            "127.0.0.1:notaport",
            "[::1]x",
            "10.0.0.1:8080",
        ] {
            assert!(!is_loopback_host(host), "{host}");
        }
    }

    #[test]
    fn tokens_compare_whole() {
        assert!(same("abc", "abc"));
        assert!(!same("abc", "abd"));
        assert!(!same("abc", "ab"));
    }
}
