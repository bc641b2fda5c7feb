//! The preview (`-gui`): its server's security and lifetime over plain HTTP, and, in headless
//! Chromium (WebGL through SwiftShader, driven by Playwright: tests/preview/drive.mjs), its
//! pictures against the staff's OpenGL viewer, the camera after dragging against raycast's own
//! render of that camera, and live editing of the scene file.
//!
//! The browser tests need Debian's `chromium` and `npm ci --prefix tests/preview`; without them
//! they say so and pass, except under CI (`CI` set), where they fail.

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

const RAYCAST: &str = env!("CARGO_BIN_EXE_raycast");

/// A raycast serving a preview, ended (and waited for) when dropped.
struct Preview {
    child: Child,
    url: String,
}

impl Preview {
    /// `raycast ARGS -port 0 -no-browser` in `dir`, once it has printed its address.
    fn start(dir: &Path, args: &[&str]) -> Preview {
        Preview::start_with(dir, args, &[])
    }

    fn start_with(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Preview {
        let mut command = Command::new(RAYCAST);
        command
            .current_dir(dir)
            .args(args)
            .args(["-port", "0", "-no-browser"])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        for (k, v) in env {
            command.env(k, v);
        }
        Preview::from_child(command.spawn().unwrap())
    }

    fn from_child(mut child: Child) -> Preview {
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        assert!(
            line.starts_with("http://127.0.0.1:") && line.contains("/?token="),
            "the first line is the address: {line:?}"
        );
        Preview {
            child,
            url: line.trim().to_string(),
        }
    }

    /// `host:port`.
    fn authority(&self) -> String {
        self.url["http://".len()..]
            .split('/')
            .next()
            .unwrap()
            .to_string()
    }

    fn token(&self) -> String {
        self.url.split("token=").nth(1).unwrap().to_string()
    }

    /// Waits for the process to end by itself, up to `limit`.
    fn exit_within(&mut self, limit: Duration) -> Option<i32> {
        let start = Instant::now();
        while start.elapsed() < limit {
            if let Some(status) = self.child.try_wait().unwrap() {
                return Some(status.code().unwrap_or(-1));
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        None
    }
}

impl Drop for Preview {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// An HTTP request to the preview: its status and body.
fn request(authority: &str, method: &str, path: &str, headers: &[(&str, &str)]) -> (u16, String) {
    let (status, body) = request_bytes(authority, method, path, headers);
    (status, String::from_utf8_lossy(&body).into_owned())
}

/// [`request`], the body as bytes.
fn request_bytes(
    authority: &str,
    method: &str,
    path: &str,
    headers: &[(&str, &str)],
) -> (u16, Vec<u8>) {
    let mut stream = TcpStream::connect(authority).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(10)))
        .unwrap();
    let host = headers
        .iter()
        .find(|(k, _)| *k == "Host")
        .map_or(authority, |(_, v)| v);
    // HTTP/1.0: the answer comes whole, not in chunks, and the connection closes after it.
    let mut text = format!("{method} {path} HTTP/1.0\r\nHost: {host}\r\n");
    for (k, v) in headers.iter().filter(|(k, _)| *k != "Host") {
        text.push_str(&format!("{k}: {v}\r\n"));
    }
    text.push_str("Content-Length: 0\r\n\r\n");
    stream.write_all(text.as_bytes()).unwrap();
    let mut answer = Vec::new();
    let _ = stream.read_to_end(&mut answer);
    let head_end = answer
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .map_or(answer.len(), |k| k + 4);
    let head = String::from_utf8_lossy(&answer[..head_end]);
    let status = head
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    (status, answer[head_end..].to_vec())
}

fn scenes() -> Option<PathBuf> {
    common::later_dir("the preview's tests").map(|d| d.join("scenes"))
}

/// A folder of our own with the scene file `scene` (and the meshes it needs) copied in.
fn scratch_with(scene: &str, meshes: &[&str]) -> Option<tempfile::TempDir> {
    let from = scenes()?;
    let dir = tempfile::tempdir().unwrap();
    for file in std::iter::once(&scene).chain(meshes) {
        std::fs::copy(from.join(file), dir.path().join(file)).unwrap();
    }
    Some(dir)
}

#[test]
fn the_server_admits_only_loopback_requests_with_the_token() {
    let Some(dir) = scratch_with("scene3_01_cube_orthographic.txt", &["cube.obj"]) else {
        return;
    };
    let before: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    let preview = Preview::start(
        dir.path(),
        &[
            "-input",
            "scene3_01_cube_orthographic.txt",
            "-size",
            "200",
            "200",
            "-output",
            "out.tga",
            "-gui",
        ],
    );
    let (at, token) = (preview.authority(), preview.token());
    let with = |path: &str| format!("{path}?token={token}");
    // No token, a wrong one, a token of the right length but wrong: refused.
    assert_eq!(request(&at, "GET", "/", &[]).0, 403);
    assert_eq!(request(&at, "GET", "/?token=nope", &[]).0, 403);
    let forged = "0".repeat(token.len());
    assert_eq!(
        request(&at, "GET", &format!("/api/scene?token={forged}"), &[]).0,
        403
    );
    assert_eq!(request(&at, "GET", "/api/geometry", &[]).0, 403);
    // A page of another site that renamed itself to 127.0.0.1 (DNS rebinding): refused, token
    // or not; loopback names with any port are admitted.
    for host in [
        "evil.example",
        "evil.example:8000",
        "127.0.0.1.evil.example",
    ] {
        let (status, body) = request(&at, "GET", &with("/api/scene"), &[("Host", host)]);
        assert_eq!(status, 403, "{host}");
        assert!(
            body.contains("is not 127.0.0.1, [::1] or localhost"),
            "{body}"
        );
    }
    for host in ["localhost:1234", "127.0.0.1", "[::1]:80"] {
        assert_eq!(
            request(&at, "GET", &with("/api/scene"), &[("Host", host)]).0,
            200,
            "{host}"
        );
    }
    // The token in the page's cookie, as the page itself sends it.
    let port = at.rsplit(':').next().unwrap();
    let cookie = format!("raycast_token_{port}={token}");
    assert_eq!(
        request(&at, "GET", "/api/scene", &[("Cookie", &cookie)]).0,
        200
    );
    let (status, body) = request(&at, "GET", &with("/"), &[]);
    assert_eq!(status, 200);
    assert!(body.contains("<canvas id=\"preview\""));
    // No path reaches the file system: not the scene, not its folder, not /etc.
    for path in [
        "/scene3_01_cube_orthographic.txt",
        "/cube.obj",
        "/../../../../etc/passwd",
        "/%2e%2e/%2e%2e/etc/passwd",
        "/api/../scene3_01_cube_orthographic.txt",
    ] {
        assert_eq!(request(&at, "GET", &with(path), &[]).0, 404, "{path}");
    }
    // Reads are GET, changes POST.
    assert_eq!(request(&at, "POST", &with("/api/scene"), &[]).0, 405);
    assert_eq!(request(&at, "GET", &with("/api/quit"), &[]).0, 405);
    // The scene's description: the staff viewer's camera and lights, the line's size.
    let (status, body) = request(&at, "GET", &with("/api/scene"), &[]);
    assert_eq!(status, 200);
    let scene: Value = serde_json::from_str(&body).unwrap();
    assert_eq!(scene["error"], Value::Null);
    assert_eq!(scene["scene"]["width"], 200);
    assert_eq!(scene["scene"]["camera"]["kind"], "orthographic");
    assert_eq!(scene["scene"]["triangles"], 12);
    // Twelve triangles, three vertices of twelve f32 each.
    let (status, geometry) = request_bytes(&at, "GET", &with("/api/geometry"), &[]);
    assert_eq!(status, 200);
    assert_eq!(geometry.len(), 12 * 3 * 12 * 4);
    // Nothing written but the image the line names.
    drop(preview);
    let mut after: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    after.sort();
    assert_eq!(before.len() + 1, after.len(), "{after:?}");
    assert_eq!(
        after,
        ["cube.obj", "out.tga", "scene3_01_cube_orthographic.txt"]
    );
}

#[test]
fn q_and_ctrl_c_end_the_preview_with_status_0() {
    let Some(dir) = scratch_with("scene3_01_cube_orthographic.txt", &["cube.obj"]) else {
        return;
    };
    let args = [
        "-input",
        "scene3_01_cube_orthographic.txt",
        "-size",
        "20",
        "20",
        "-output",
        "o.tga",
        "-gui",
    ];
    let mut preview = Preview::start(dir.path(), &args);
    let at = preview.authority();
    let quit = format!("/api/quit?token={}", preview.token());
    // An open event stream does not keep it alive.
    let mut stream = TcpStream::connect(&at).unwrap();
    write!(
        stream,
        "GET /api/events?token={} HTTP/1.1\r\nHost: {at}\r\n\r\n",
        preview.token()
    )
    .unwrap();
    assert_eq!(request(&at, "POST", &quit, &[]).0, 204);
    assert_eq!(preview.exit_within(Duration::from_secs(5)), Some(0));
    assert!(
        dir.path().join("o.tga").is_file(),
        "the image is written at the start"
    );

    let mut preview = Preview::start(dir.path(), &args);
    let status = Command::new("kill")
        .args(["-INT", &preview.child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    assert_eq!(preview.exit_within(Duration::from_secs(5)), Some(0));
}

#[test]
fn without_a_terminal_or_port_gui_writes_the_image_and_returns() {
    let Some(dir) = scratch_with("scene3_01_cube_orthographic.txt", &["cube.obj"]) else {
        return;
    };
    let output = Command::new(RAYCAST)
        .current_dir(dir.path())
        .args([
            "-input",
            "scene3_01_cube_orthographic.txt",
            "-size",
            "20",
            "20",
        ])
        .args([
            "-output",
            "o.tga",
            "-gui",
            "-tessellation",
            "10",
            "5",
            "-gouraud",
        ])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    assert!(output.status.success());
    assert!(output.stdout.is_empty());
    assert_eq!(
        String::from_utf8_lossy(&output.stderr).trim(),
        "raycast: -gui: standard input is not a terminal, so no preview is served (add -port N \
         to serve one); the images are written as without -gui"
    );
    assert!(dir.path().join("o.tga").is_file());
    // Refused: the preview's address and an image both on standard output; -port without -gui.
    let refused = |args: &[&str], message: &str| {
        let output = Command::new(RAYCAST)
            .current_dir(dir.path())
            .args([
                "-input",
                "scene3_01_cube_orthographic.txt",
                "-size",
                "20",
                "20",
            ])
            .args(args)
            .stdin(Stdio::null())
            .output()
            .unwrap();
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            stderr.starts_with(&format!("raycast: {message}")),
            "{stderr}"
        );
    };
    refused(
        &["-output", "-", "-format", "png", "-gui", "-port", "0"],
        "-gui prints the preview's address on standard output: write the images to files, not -",
    );
    refused(
        &["-output", "o.tga", "-port", "0"],
        "-port and -no-browser serve -gui's preview: add -gui",
    );
    refused(
        &["-output", "o.tga", "-gui", "-port", "70000"],
        "-port needs a port number (a whole number from 0 to 65535), found '70000'",
    );
}

// ---- In the browser ----

/// Whether the browser tests can run: Chromium and the driver installed. Under CI, missing
/// either fails.
fn browser() -> bool {
    let driver =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/preview/node_modules/playwright-core");
    let chromium = std::env::var("RAYCAST_CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into());
    let node = Command::new("node")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    let ready = driver.is_dir() && Path::new(&chromium).is_file() && node;
    if !ready {
        let why = format!(
            "the preview's browser tests need node, {chromium} (apt-get install chromium) and \
             tests/preview/node_modules (npm ci --prefix tests/preview)"
        );
        assert!(std::env::var_os("CI").is_none(), "{why}");
        eprintln!("skipped: {why}");
    }
    ready
}

/// Runs the drive script's `steps` against `url`; its report.
fn drive(url: &str, steps: Value) -> Value {
    let script = tempfile::NamedTempFile::new().unwrap();
    std::fs::write(
        script.path(),
        json!({ "url": url, "steps": steps }).to_string(),
    )
    .unwrap();
    let output = Command::new("node")
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/preview"))
        .arg("drive.mjs")
        .arg(script.path())
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "drive.mjs: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let report: Value = serde_json::from_slice(&output.stdout).unwrap();
    let errors = report["console"].as_array().unwrap();
    assert!(errors.is_empty(), "the page's console: {errors:?}");
    report
}

fn rgb(path: &Path) -> image::RgbImage {
    image::open(path).unwrap().to_rgb8()
}

/// The share of the canvas's pixels off by more than 8 levels in some channel from the GL
/// area of a staff grab (the W × H block 4 pixels from the left, 20 from the top).
fn off_from_grab(canvas: &image::RgbImage, grab: &image::RgbImage) -> f64 {
    let (w, h) = canvas.dimensions();
    let mut off = 0;
    for (x, y, p) in canvas.enumerate_pixels() {
        let q = grab.get_pixel(x + 4, y + 20);
        if p.0.iter().zip(q.0).any(|(a, b)| a.abs_diff(b) > 8) {
            off += 1;
        }
    }
    f64::from(off) / f64::from(w * h)
}

#[test]
fn the_preview_draws_as_the_staffs_viewer() {
    let Some(scenes) = scenes() else { return };
    if !browser() {
        return;
    }
    let grabs = scenes.parent().unwrap().join("reference/a3");
    let lines = std::fs::read_to_string(grabs.join("VIEWERS.txt")).unwrap();
    let out = tempfile::tempdir().unwrap();
    let mut table = vec!["grab | pixels off by more than 8 levels".to_string()];
    let mut worst: f64 = 0.0;
    for line in lines.lines().filter(|l| l.starts_with("viewer")) {
        let mut words = line.split_whitespace();
        let name = words.next().unwrap();
        let mut args: Vec<String> = words.skip(1).map(String::from).collect();
        let at = args.iter().position(|a| a == "-output").unwrap();
        args[at + 1] = out
            .path()
            .join(format!("{name}.tga"))
            .to_string_lossy()
            .into_owned();
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let mut preview = Preview::start(&scenes, &args);
        let canvas = out.path().join(format!("{name}.png"));
        drive(&preview.url, json!([{ "canvas": canvas }, { "key": "q" }]));
        assert_eq!(
            preview.exit_within(Duration::from_secs(5)),
            Some(0),
            "{name}: 'q' quits"
        );
        let off = off_from_grab(&rgb(&canvas), &rgb(&grabs.join(format!("{name}.png"))));
        table.push(format!("{name} | {:.3}%", 100.0 * off));
        worst = worst.max(off);
    }
    println!("{}", table.join("\n"));
    assert!(worst <= 0.01, "{}", table.join("\n"));
}

/// Which pixels show the background colour `background`.
fn mask(picture: &image::RgbImage, background: [u8; 3]) -> Vec<bool> {
    picture.pixels().map(|p| p.0 != background).collect()
}

/// The scene file `text` with its camera block replaced by `camera`.
fn with_camera(text: &str, camera: &str) -> String {
    let start = text
        .find("Camera")
        .and_then(|k| {
            text[..k]
                .rfind(|c: char| c.is_whitespace())
                .map(|s| s + 1)
                .or(Some(0))
        })
        .unwrap();
    let end = start + text[start..].find('}').unwrap() + 1;
    format!("{}{camera}{}", &text[..start], &text[end..])
}

#[test]
fn after_dragging_the_preview_sees_what_raycast_renders_of_its_camera() {
    let Some(dir) = scratch_with("scene3_01_cube_orthographic.txt", &["cube.obj"]) else {
        return;
    };
    if !browser() {
        return;
    }
    let from = scenes().unwrap();
    std::fs::copy(
        from.join("scene3_02_cube_perspective.txt"),
        dir.path().join("scene3_02_cube_perspective.txt"),
    )
    .unwrap();
    for scene in [
        "scene3_01_cube_orthographic.txt",
        "scene3_02_cube_perspective.txt",
    ] {
        let preview = Preview::start(
            dir.path(),
            &[
                "-input", scene, "-size", "200", "200", "-output", "o.tga", "-gui",
            ],
        );
        let canvas = dir.path().join("moved.png");
        // Each button: rotate, truck, dolly.
        drive(
            &preview.url,
            json!([
                { "drag": [0, [100, 100], [140, 80], 8] },
                { "drag": [1, [100, 100], [90, 110], 5] },
                { "drag": [2, [100, 100], [110, 100], 5] },
                { "canvas": canvas },
            ]),
        );
        let (status, camera) = request(
            &preview.authority(),
            "GET",
            &format!("/api/camera?token={}", preview.token()),
            &[],
        );
        assert_eq!(status, 200);
        let original = std::fs::read_to_string(dir.path().join(scene)).unwrap();
        assert!(camera.contains("Camera {"), "{camera}");
        let moved = dir.path().join("moved.txt");
        std::fs::write(&moved, with_camera(&original, &camera)).unwrap();
        let rendered = dir.path().join("moved_render.png");
        let status = Command::new(RAYCAST)
            .current_dir(dir.path())
            .args(["-input", "moved.txt", "-size", "200", "200", "-output"])
            .arg(&rendered)
            .status()
            .unwrap();
        assert!(status.success());
        let background = [51, 0, 153];
        let (a, b) = (
            mask(&rgb(&canvas), background),
            mask(&rgb(&rendered), background),
        );
        let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        let objects = b.iter().filter(|x| **x).count();
        assert!(
            objects > 2000,
            "{scene}: the cube is in view after the drags ({objects} pixels)"
        );
        let original_render = dir.path().join("o.tga");
        let unmoved = mask(&rgb(&original_render), background);
        assert_ne!(unmoved, b, "{scene}: the drags moved the camera");
        assert!(
            differ as f64 <= 0.01 * 200.0 * 200.0,
            "{scene}: {differ} pixels of the masks differ\n{camera}"
        );
    }
}

#[test]
fn editing_the_scene_redraws_it_and_shows_its_errors() {
    let Some(dir) = scratch_with("scene3_01_cube_orthographic.txt", &["cube.obj"]) else {
        return;
    };
    if !browser() {
        return;
    }
    let scene = dir.path().join("scene3_01_cube_orthographic.txt");
    let good = std::fs::read_to_string(&scene).unwrap();
    let green = good.replace("color 0.2 0 0.6", "color 0 0.8 0");
    assert_ne!(green, good);
    let broken = green.replace("numMaterials 1", "numMaterials one");
    let preview = Preview::start(
        dir.path(),
        &[
            "-input",
            "scene3_01_cube_orthographic.txt",
            "-size",
            "200",
            "200",
            "-output",
            "o.tga",
            "-gui",
        ],
    );
    let out = dir.path();
    let report = drive(
        &preview.url,
        json!([
            { "drag": [0, [100, 100], [120, 100], 4] },
            { "eval": "document.getElementById('camera').textContent" },
            // As an editor saves: a new file renamed over the old.
            { "save": [scene, green] },
            { "wait_eval": "scene.background[1] > 0.7 && !pending" },
            { "canvas": out.join("green.png") },
            { "eval": "document.getElementById('camera').textContent" },
            { "save": [scene, broken] },
            { "wait_text": ["#error", "numMaterials, found 'one'"] },
            { "eval": "document.getElementById('error').textContent" },
            { "canvas": out.join("still.png") },
            { "save": [scene, good] },
            { "wait_eval": "document.getElementById('error').textContent === '' && scene.background[1] === 0 && !pending" },
            // A render, then an edit: the render is the old scene's, and says so.
            { "key": "r" },
            { "wait_eval": "document.body.dataset.render === '1'" },
            { "eval": "document.body.dataset.stale === undefined" },
            { "save": [scene, green] },
            { "wait_eval": "document.body.dataset.stale === '1'" },
            { "eval": "[document.getElementById('rendered').classList.contains('stale'), (document.getElementById('stats').textContent === '' || document.getElementById('stats').classList.contains('stale')), document.getElementById('render-status').textContent].join('|')" },
            // Nothing moves: no frame is drawn, and the rate says idle rather than 0.
            { "wait_ms": 1600 },
            { "eval": "document.getElementById('fps').textContent" },
            { "key": "q" },
        ]),
    );
    let steps = report["steps"].as_array().unwrap();
    let value = |k: usize| steps[k]["value"].as_str().unwrap_or_default().to_string();
    // The camera stays where the mouse left it across the reload.
    assert_eq!(value(1), value(5));
    let green_picture = rgb(&out.join("green.png"));
    assert_eq!(green_picture.get_pixel(0, 0).0, [0, 204, 0]);
    // The error as the command line prints it (file:line:col, the line, the message); the last
    // good scene stays drawn.
    let error = value(8);
    assert!(
        error.ends_with(
            "scene3_01_cube_orthographic.txt:23:18: expected a whole number from 0 to 4294967295 \
             for numMaterials, found 'one'"
        ),
        "{error}"
    );
    assert_eq!(rgb(&out.join("still.png")), green_picture);
    assert_eq!(steps[14]["value"], true, "{:?}", steps[14]);
    assert_eq!(
        value(17),
        "true|true|stale: the scene changed since; press r to render it again, t for a ray tree"
    );
    // (wait_ms adds no step to the report.)
    assert_eq!(value(18), "idle");
    let redraw_ms = steps[3]["ms"].as_u64().unwrap();
    println!("redrawn {redraw_ms} ms after the save");
}

#[test]
fn an_open_tab_reconnects_when_raycast_starts_again_on_its_port() {
    let Some(dir) = scratch_with("scene3_01_cube_orthographic.txt", &["cube.obj"]) else {
        return;
    };
    if !browser() {
        return;
    }
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
        .to_string();
    let token = "reconnect0123456789abcdef";
    let start = || {
        let child = Command::new(RAYCAST)
            .current_dir(dir.path())
            .args([
                "-input",
                "scene3_01_cube_orthographic.txt",
                "-size",
                "50",
                "50",
            ])
            .args(["-output", "o.tga", "-gui", "-no-browser", "-port", &port])
            .env("RAYCAST_PREVIEW_TOKEN", token)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        Preview::from_child(child)
    };
    let mut first = start();
    assert_eq!(first.token(), token);
    let url = first.url.clone();
    let page = std::thread::spawn(move || {
        drive(
            &url,
            json!([
                { "key": "q" },
                { "wait_text": ["#status", "lost"] },
                { "wait_text": ["#status", "connected"] },
                { "eval": "document.body.dataset.frame" },
            ]),
        )
    });
    assert_eq!(first.exit_within(Duration::from_secs(10)), Some(0));
    std::thread::sleep(Duration::from_millis(500));
    let mut second = start();
    let report = page.join().unwrap();
    let waited = report["steps"][2]["ms"].as_u64().unwrap();
    println!("reconnected after {waited} ms");
    let (status, _) = request(
        &second.authority(),
        "POST",
        &format!("/api/quit?token={token}"),
        &[],
    );
    assert_eq!(status, 204);
    assert_eq!(second.exit_within(Duration::from_secs(5)), Some(0));
}

/// The course's lines of `prefix` scenes, as argument lists (without `raytracer`), their image
/// named `name` and their preview options dropped (the tests add their own).
fn course_lines_of(prefix: &str) -> Vec<Vec<String>> {
    let later = common::later_dir("the preview's tools").unwrap();
    common::course_lines(&later, &[prefix])
        .into_iter()
        .map(|args| {
            let mut kept = Vec::new();
            let mut words = args.into_iter();
            while let Some(word) = words.next() {
                match word.as_str() {
                    "-gui" | "-gouraud" => {}
                    "-tessellation" => {
                        words.next();
                        words.next();
                    }
                    _ => kept.push(word),
                }
            }
            kept
        })
        .collect()
}

/// `args` with the value after `flag` set to `value`.
fn with_value(args: &[String], flag: &str, value: &str) -> Vec<String> {
    let mut args = args.to_vec();
    let at = args.iter().position(|a| a == flag).unwrap();
    args[at + 1] = value.to_string();
    args
}

fn strs(args: &[String]) -> Vec<&str> {
    args.iter().map(String::as_str).collect()
}

#[test]
fn r_renders_the_view_as_the_command_line_does() {
    let Some(scenes) = scenes() else { return };
    let out = tempfile::tempdir().unwrap();
    let mut lines = course_lines_of("scene4_");
    lines.truncate(10);
    assert_eq!(lines.len(), 10);
    for (k, line) in lines.iter().enumerate() {
        let batch = out.path().join(format!("batch{k}.tga"));
        let status = Command::new(RAYCAST)
            .current_dir(&scenes)
            .args(strs(&with_value(line, "-output", batch.to_str().unwrap())))
            .status()
            .unwrap();
        assert!(status.success());
        let viewed = out.path().join(format!("viewed{k}.tga"));
        let mut args = with_value(line, "-output", viewed.to_str().unwrap());
        args.push("-gui".into());
        let preview = Preview::start(&scenes, &strs(&args));
        // The line's image is written at the start; 'r' writes it again.
        let start = Instant::now();
        while !viewed.is_file() && start.elapsed() < Duration::from_secs(20) {
            std::thread::sleep(Duration::from_millis(20));
        }
        std::fs::remove_file(&viewed).unwrap();
        // 'r' at the initial view (no page has moved the camera): the batch image's bytes.
        let (status, png) = request_bytes(
            &preview.authority(),
            "POST",
            &format!("/api/render?token={}", preview.token()),
            &[],
        );
        assert_eq!(status, 200);
        assert_eq!(
            std::fs::read(&viewed).unwrap(),
            std::fs::read(&batch).unwrap(),
            "{line:?}"
        );
        let shown = image::load_from_memory(&png).unwrap().to_rgb8();
        assert_eq!(shown, rgb(&batch), "the page gets the same picture");
    }
    // With -stats, 'r' gives the course's block as the command line prints it.
    let line = with_value(
        &lines[3],
        "-output",
        out.path().join("s.tga").to_str().unwrap(),
    );
    let mut args = line.clone();
    args.push("-stats".into());
    let printed = Command::new(RAYCAST)
        .current_dir(&scenes)
        .args(strs(&args))
        .output()
        .unwrap();
    args.push("-gui".into());
    let preview = Preview::start(&scenes, &strs(&args));
    let mut stream = TcpStream::connect(preview.authority()).unwrap();
    write!(
        stream,
        "POST /api/render?token={} HTTP/1.0\r\nHost: {}\r\n\r\n",
        preview.token(),
        preview.authority()
    )
    .unwrap();
    let mut answer = Vec::new();
    stream.read_to_end(&mut answer).unwrap();
    let answer = String::from_utf8_lossy(&answer);
    let stats = answer
        .lines()
        .find_map(|l| l.strip_prefix("X-Render-Stats: "))
        .expect("the stats header");
    let stats: String = serde_json::from_str(stats).unwrap();
    assert_eq!(stats, String::from_utf8(printed.stdout).unwrap());
}

/// `raycast ARGS -inspect X Y [-json]` in `dir`: what it prints.
fn inspect(dir: &Path, args: &[&str], (x, y): (u32, u32), json: bool) -> String {
    let output = Command::new(RAYCAST)
        .current_dir(dir)
        .args(args)
        .args(["-inspect", &x.to_string(), &y.to_string()])
        .args(if json { &["-json"][..] } else { &[][..] })
        .output()
        .unwrap();
    assert!(output.status.success());
    String::from_utf8(output.stdout).unwrap()
}

#[test]
fn the_ray_tree_endpoint_answers_as_inspect_does() {
    let Some(scenes) = scenes() else { return };
    let out = tempfile::tempdir().unwrap();
    let lines = course_lines_of("scene4_");
    // Every scene of assignment 4, once (its first line).
    let mut seen = Vec::new();
    for line in lines {
        let scene = line[1].clone();
        if seen.contains(&scene) {
            continue;
        }
        seen.push(scene.clone());
        let line = with_value(&line, "-output", out.path().join("o.tga").to_str().unwrap());
        let mut args = line.clone();
        args.push("-gui".into());
        let preview = Preview::start(&scenes, &strs(&args));
        let (w, h) = (200, 200);
        for pixel in [
            (w / 2, h / 2),
            (10, 10),
            (w - 11, 25),
            (37, h - 5),
            (150, 120),
        ] {
            let path = format!(
                "/api/raytree?x={}&y={}&token={}",
                pixel.0,
                pixel.1,
                preview.token()
            );
            let (status, body) = request(&preview.authority(), "GET", &path, &[]);
            assert_eq!(status, 200);
            assert_eq!(
                body,
                inspect(&scenes, &strs(&line), pixel, true),
                "{scene} {pixel:?}"
            );
            let (_, text) = request(
                &preview.authority(),
                "GET",
                &format!("{path}&format=text"),
                &[],
            );
            assert_eq!(
                text,
                inspect(&scenes, &strs(&line), pixel, false),
                "{scene} {pixel:?}"
            );
        }
        // After the page moved the camera: the tree of the moved view, as -inspect gives it for
        // the scene file with that camera.
        let original = std::fs::read_to_string(scenes.join(&scene)).unwrap();
        let moved_camera = "PerspectiveCamera {\n    center 1 2 12\n    direction -0.1 -0.15 -1\n    up 0 1 0\n    angle 35\n}";
        let body = moved_camera.as_bytes();
        let mut stream = TcpStream::connect(preview.authority()).unwrap();
        write!(
            stream,
            "POST /api/camera?token={} HTTP/1.0\r\nHost: {}\r\nContent-Length: {}\r\n\r\n",
            preview.token(),
            preview.authority(),
            body.len()
        )
        .unwrap();
        stream.write_all(body).unwrap();
        let mut answer = String::new();
        stream.read_to_string(&mut answer).unwrap();
        assert!(answer.contains(" 204 "), "{answer}");
        let moved = out.path().join("moved.txt");
        std::fs::write(&moved, with_camera(&original, moved_camera)).unwrap();
        let moved_line = with_value(&line, "-input", moved.to_str().unwrap());
        let path = format!("/api/raytree?x=100&y=100&token={}", preview.token());
        let (_, body) = request(&preview.authority(), "GET", &path, &[]);
        assert_eq!(
            body,
            inspect(&scenes, &strs(&moved_line), (100, 100), true),
            "{scene} moved"
        );
    }
    assert_eq!(seen.len(), 14, "{seen:?}");
    // A pixel outside the image, or none: refused with the reason.
    let line = course_lines_of("scene4_01").remove(0);
    let mut args = with_value(&line, "-output", out.path().join("o.tga").to_str().unwrap());
    args.push("-gui".into());
    let preview = Preview::start(&scenes, &strs(&args));
    let at = preview.authority();
    let (status, body) = request(
        &at,
        "GET",
        &format!("/api/raytree?x=200&y=0&token={}", preview.token()),
        &[],
    );
    assert_eq!(
        (status, body.as_str()),
        (400, "pixel (200, 0) is outside the 200x200 image")
    );
    let (status, _) = request(
        &at,
        "GET",
        &format!("/api/raytree?token={}", preview.token()),
        &[],
    );
    assert_eq!(status, 400);
}

/// A point of the first shadow ray of the tree drawn, on the canvas and clear of the hit point
/// where the tree's other rays meet it.
const SHADOW_POINT: &str = "(() => {
    const line = treeLines.find((l) => l.light !== null);
    const [a, b] = line.segment;
    const m = matrices(canvas.width, canvas.height);
    const screen = (p) => {
        const c = [0, 1, 2, 3].map((r) => m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r]);
        return [((c[0] / c[3] + 1) / 2) * canvas.width, ((1 - c[1] / c[3]) / 2) * canvas.height];
    };
    const start = screen(a);
    for (const f of [0.01, 0.02, 0.05, 0.1, 0.2, 0.3]) {
        const p = screen([0, 1, 2].map((k) => a[k] + f * (b[k] - a[k])));
        const inside = p[0] > 2 && p[1] > 2 && p[0] < canvas.width - 2 && p[1] < canvas.height - 2;
        if (inside && Math.hypot(p[0] - start[0], p[1] - start[1]) > 12) return p;
    }
    return start;
})()";

fn steps_value(report: &Value, k: usize) -> String {
    report["steps"][k]["value"]
        .as_str()
        .unwrap_or_default()
        .to_string()
}

#[test]
fn the_keys_render_and_trace_in_the_page() {
    let Some(scenes) = scenes() else { return };
    if !browser() {
        return;
    }
    let out = tempfile::tempdir().unwrap();
    let line = course_lines_of("scene4_03").remove(0);
    let line = with_value(&line, "-output", out.path().join("o.tga").to_str().unwrap());
    let mut args = line.clone();
    args.push("-gui".into());
    let preview = Preview::start(&scenes, &strs(&args));
    let before = out.path().join("before.png");
    let after = out.path().join("after.png");
    let report = drive(
        &preview.url,
        json!([
            { "canvas": before },
            { "move": [100, 100] },
            { "key": "t" },
            { "wait_eval": "document.body.dataset.tree !== undefined && !pending" },
            { "canvas": after },
            { "eval": "document.body.dataset.tree" },
            { "eval": "document.getElementById('inspect').textContent" },
            { "key": "r" },
            { "wait_eval": "document.body.dataset.render === '1'" },
            { "eval": "document.getElementById('rendered').naturalWidth" },
            // A click on a shadow ray's segment highlights its light's line in the account.
            { "click_eval": SHADOW_POINT },
            { "eval": "document.body.dataset.highlighted" },
        ]),
    );
    let highlighted = steps_value(&report, 11);
    assert!(
        highlighted.starts_with("light ") && highlighted.contains("shadow ray"),
        "{highlighted}"
    );
    let steps = report["steps"].as_array().unwrap();
    // The staff's mapping: the mouse's row 100 of 200 is pixel row 200 - 100 = 100.
    assert_eq!(steps[5]["value"], "100,100");
    assert_eq!(
        steps[6]["value"].as_str().unwrap(),
        inspect(&scenes, &strs(&line), (100, 100), false)
    );
    // The tree is drawn over the scene (the camera ray seen end on is a point; its shadow and
    // mirror rays are lines).
    let (a, b) = (rgb(&before), rgb(&after));
    let changed: Vec<[u8; 3]> = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p != q)
        .map(|(_, q)| q.0)
        .collect();
    assert!(changed.len() > 20, "{} pixels changed", changed.len());
    assert_eq!(steps[9]["value"], 200);
}

/// The options of a course line run in `scenes`.
fn options_of(scenes: &Path, line: &[String]) -> raycast::job::Options {
    let args: Vec<std::ffi::OsString> = line.iter().map(Into::into).collect();
    match raycast::job::parse_args(args).unwrap() {
        raycast::job::Command::Render(options) => {
            let mut options = *options;
            options.input = scenes.join(&options.input);
            options
        }
        _ => panic!("not a render"),
    }
}

#[test]
fn the_grid_cells_a_tree_walks_are_the_renders_own() {
    let Some(scenes) = scenes() else { return };
    let out = tempfile::tempdir().unwrap();
    let lines: Vec<Vec<String>> = course_lines_of("scene5_")
        .into_iter()
        .filter(|l| l.iter().any(|a| a == "-grid") && l.iter().any(|a| a == "-output"))
        .collect();
    assert!(lines.len() >= 8, "{}", lines.len());
    for line in lines {
        let line = with_value(&line, "-output", out.path().join("o.tga").to_str().unwrap());
        let mut options = options_of(&scenes, &line);
        // The camera ray alone, walked through the grid as the render's search walks it, its
        // cells counted by the render's own tally.
        options.trace.visualize_grid = false;
        options.trace.shadows = false;
        options.trace.bounces = 0;
        let scene = raycast::preview::scene_at(&options, None).unwrap();
        let grid = raycast::preview::grid(&options).unwrap();
        let occupied = scene.world.grid().unwrap().occupancy().0;
        assert_eq!(grid["occupied"].as_array().unwrap().len(), occupied);
        let settings = raycast::trace::TraceSettings {
            tally: true,
            ..options.trace
        };
        let tracer = raycast::trace::Tracer::new(&scene, settings);
        for k in 0..20u32 {
            let pixel = ((k * 37 + 11) % 200, (k * 53 + 29) % 200);
            let walk = raycast::preview::grid_walk(&options, None, pixel).unwrap();
            let cells = walk["rays"][0]["cells"].as_array().unwrap().len() as u64;
            let (u, v) = raycast::camera::pixel_to_screen(pixel.0, pixel.1, 200, 200);
            let ray = scene.camera.ray(u, v);
            let mut scratch = raycast::trace::Scratch::default();
            tracer.camera_ray(&ray, false, &mut scratch);
            assert_eq!(cells, scratch.counts.tallies.cells, "{line:?} {pixel:?}");
        }
    }
}

#[test]
fn g_cycles_through_the_grids_views() {
    let Some(scenes) = scenes() else { return };
    if !browser() {
        return;
    }
    let out = tempfile::tempdir().unwrap();
    let line = course_lines_of("scene5_02_spheres").remove(0);
    let line = with_value(&line, "-output", out.path().join("o.tga").to_str().unwrap());
    let mut args = line.clone();
    args.push("-gui".into());
    let preview = Preview::start(&scenes, &strs(&args));
    let pictures: Vec<PathBuf> = (0..4)
        .map(|k| out.path().join(format!("g{k}.png")))
        .collect();
    let report = drive(
        &preview.url,
        json!([
            // -visualize_grid: the preview starts on the occupied cells.
            { "eval": "document.body.dataset.grid" },
            { "canvas": pictures[0] },
            { "move": [100, 100] },
            { "key": "t" },
            { "wait_eval": "document.body.dataset.tree !== undefined && !pending" },
            { "key": "g" },
            { "wait_eval": "document.body.dataset.grid === 'cells the ray tree walked' && !pending" },
            { "canvas": pictures[1] },
            { "key": "g" },
            { "wait_eval": "document.body.dataset.grid === 'faces the ray tree entered' && !pending" },
            { "canvas": pictures[2] },
            { "key": "g" },
            { "wait_eval": "document.body.dataset.grid === 'scene' && !pending" },
            { "canvas": pictures[3] },
        ]),
    );
    assert_eq!(report["steps"][0]["value"], "occupied cells");
    let pictures: Vec<image::RgbImage> = pictures.iter().map(|p| rgb(p)).collect();
    for a in 0..4 {
        for b in a + 1..4 {
            assert_ne!(pictures[a], pictures[b], "views {a} and {b} are the same");
        }
    }
    // Without -grid, 'g' says so.
    let plain = course_lines_of("scene4_01").remove(0);
    let mut args = with_value(
        &plain,
        "-output",
        out.path().join("p.tga").to_str().unwrap(),
    );
    args.push("-gui".into());
    let preview = Preview::start(&scenes, &strs(&args));
    let report = drive(
        &preview.url,
        json!([
            { "key": "g" },
            { "wait_text": ["#render-status", "no grid"] },
        ]),
    );
    assert!(report["steps"].as_array().unwrap().len() == 2);
}
