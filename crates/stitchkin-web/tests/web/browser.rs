//! The page end to end in headless Chromium, driven over the DevTools
//! protocol as a user would: load it, click the r1 slider further along,
//! and check that the take-up chart, the summary and the mechanism were
//! redrawn. A screenshot is saved as a test artifact
//! (`target/tmp/browser/serve-mf7923d*.png`).
//!
//! Chromium is Debian's package `chromium` (`.ci/run` installs it and sets
//! STITCHKIN_REQUIRE_BROWSER=1, so there a missing browser fails the test);
//! elsewhere, without it, the test says loudly that it did not run.
//! STITCHKIN_CHROMIUM names another binary.

use std::io::{BufRead, BufReader, Write};
use std::net::TcpStream;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use base64::Engine;
use serde_json::{Value, json};
use tungstenite::stream::MaybeTlsStream;
use tungstenite::{Message, WebSocket};

fn chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("STITCHKIN_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH")?;
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |dir| dir.join(name)))
        .find(|p| p.is_file())
}

/// A headless Chromium and a DevTools connection to one of its pages.
struct Browser {
    child: Child,
    ws: WebSocket<MaybeTlsStream<TcpStream>>,
    next_id: u64,
    session: Option<String>,
    _profile: TempDir,
}

struct TempDir(PathBuf);
impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

impl Browser {
    fn launch(exe: &PathBuf) -> Browser {
        let profile = TempDir(std::env::temp_dir().join(format!("stitchkin-chromium-{}", std::process::id())));
        std::fs::create_dir_all(&profile.0).unwrap();
        // The flags keep Chromium off the network (this machine's is closed)
        // and out of the sandbox, which needs privileges CI may not have.
        let mut child = Command::new(exe)
            .args([
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-quic",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                "--remote-debugging-port=0",
                "--window-size=1400,2600",
            ])
            .arg(format!("--user-data-dir={}", profile.0.display()))
            // Chromium also writes beside the profile (crash reports, NSS
            // keys): keep that in the throw-away folder, not the user's home.
            .env("HOME", &profile.0)
            .env("XDG_CONFIG_HOME", profile.0.join("config"))
            .env("XDG_CACHE_HOME", profile.0.join("cache"))
            .arg("about:blank")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {}: {e}", exe.display()));
        // Chromium says where DevTools listen on stderr.
        let stderr = child.stderr.take().unwrap();
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                if let Some(url) = line.split("DevTools listening on ").nth(1) {
                    let _ = tx.send(url.trim().to_string());
                }
            }
        });
        let url = match rx.recv_timeout(Duration::from_secs(60)) {
            Ok(url) => url,
            Err(_) => {
                let _ = child.kill();
                panic!("{} did not open DevTools within 60 s", exe.display());
            }
        };
        let (ws, _) = tungstenite::connect(url.as_str()).expect("DevTools websocket");
        if let MaybeTlsStream::Plain(s) = ws.get_ref() {
            s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
        }
        Browser {
            child,
            ws,
            next_id: 0,
            session: None,
            _profile: profile,
        }
    }

    /// One DevTools command, its result (events in between are skipped).
    fn call(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        let mut msg = json!({ "id": id, "method": method, "params": params });
        if let Some(s) = &self.session {
            msg["sessionId"] = json!(s);
        }
        self.ws.send(Message::text(msg.to_string())).unwrap();
        loop {
            let m = self
                .ws
                .read()
                .unwrap_or_else(|e| panic!("{method}: no answer from Chromium ({e})"));
            let Message::Text(text) = m else { continue };
            let v: Value = serde_json::from_str(&text).unwrap();
            if v["id"] == id {
                assert!(v.get("error").is_none(), "{method}: {}", v["error"]);
                return v["result"].clone();
            }
        }
    }

    /// Opens a tab and sends the next commands to it.
    fn open_tab(&mut self) {
        let target = self.call("Target.createTarget", json!({ "url": "about:blank" }));
        let attached = self.call(
            "Target.attachToTarget",
            json!({ "targetId": target["targetId"], "flatten": true }),
        );
        self.session = Some(attached["sessionId"].as_str().unwrap().to_string());
        self.call("Page.enable", json!({}));
        // Tall enough for the whole page: screenshots need not capture
        // beyond the viewport (which re-lays the page out and can move an
        // element between a mouse press and its release).
        self.call(
            "Emulation.setDeviceMetricsOverride",
            json!({ "width": 1400, "height": 2600, "deviceScaleFactor": 1, "mobile": false }),
        );
    }

    /// Evaluates `js` in the page and returns its value.
    fn eval(&mut self, js: &str) -> Value {
        let r = self.call(
            "Runtime.evaluate",
            json!({ "expression": js, "returnByValue": true, "awaitPromise": true }),
        );
        assert!(r.get("exceptionDetails").is_none(), "{js}: {}", r["exceptionDetails"]);
        r["result"]["value"].clone()
    }

    /// Waits until `js` is true (polling), or fails saying what it waited for.
    fn wait_for(&mut self, js: &str, what: &str) {
        let deadline = Instant::now() + Duration::from_secs(120);
        while Instant::now() < deadline {
            if self.eval(js) == json!(true) {
                return;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        let error = self.eval("document.getElementById('error').textContent");
        panic!("timed out waiting for {what} (page error box: {error})");
    }

    /// A left click at page coordinates (x, y) px.
    fn click(&mut self, x: f64, y: f64) {
        for kind in ["mouseMoved", "mousePressed", "mouseReleased"] {
            self.call(
                "Input.dispatchMouseEvent",
                json!({ "type": kind, "x": x, "y": y, "button": "left", "clickCount": 1 }),
            );
        }
    }

    /// Saves a PNG of the whole page under the test artifacts.
    fn screenshot(&mut self, name: &str) -> PathBuf {
        let shot = self.call("Page.captureScreenshot", json!({ "format": "png" }));
        let png = base64::engine::general_purpose::STANDARD
            .decode(shot["data"].as_str().unwrap())
            .unwrap();
        assert_eq!(&png[1..4], b"PNG");
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("browser");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, png).unwrap();
        path
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        self.session = None;
        let _ = self
            .ws
            .send(Message::text(json!({ "id": 0, "method": "Browser.close" }).to_string()));
        std::thread::sleep(Duration::from_millis(200));
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The page is ready and nothing is being computed.
const SETTLED: &str = "window.stitchkinReady === true && document.body.dataset.pending === '0'";

#[test]
fn moving_a_slider_redraws_the_take_up_summary_and_mechanism() {
    let Some(exe) = chromium() else {
        if std::env::var_os("STITCHKIN_REQUIRE_BROWSER").is_some() {
            panic!(
                "STITCHKIN_REQUIRE_BROWSER is set but no Chromium was found: install Debian's package `chromium` (or set STITCHKIN_CHROMIUM)"
            );
        }
        // Written to the process's stderr itself: the test harness captures
        // `eprintln!` of a passing test, which would hide the skip.
        let _ = writeln!(
            std::io::stderr(),
            "\n\n!!!! SKIPPED the browser test: no Chromium on PATH. Install Debian's package `chromium` to run it (.ci/run does). !!!!\n"
        );
        return;
    };
    let server = super::http::start("mf7923d");
    let mut b = Browser::launch(&exe);
    b.open_tab();
    b.call("Page.navigate", json!({ "url": server.url() }));
    b.wait_for(SETTLED, "the page's first drawing");

    let chart = "document.querySelector('#chart svg').outerHTML";
    let table = "document.querySelector('#paths').textContent";
    let drawing = "document.querySelector('#drawing svg').outerHTML";
    let (chart0, table0, drawing0) = (b.eval(chart), b.eval(table), b.eval(drawing));
    assert!(chart0.as_str().unwrap().contains("polyline"), "a chart with curves");
    assert_eq!(b.eval("document.getElementById('p-r1').value"), json!("4"));
    assert_eq!(
        b.eval("document.querySelectorAll('#adjustable input[type=range]').length"),
        // r1, l_o2b, z, dphi, t1_phase and the thread's EA, breaking force,
        // regulator and clamp holds.
        json!(9),
        "a slider per adjustable parameter"
    );
    assert_eq!(
        b.eval("document.querySelectorAll('#stitch input[type=number]').length"),
        json!(2),
        "thickness and stitch length inputs"
    );
    b.screenshot("serve-mf7923d-before.png");

    // Click the r1 slider at 85 % of its length: r1 jumps to about 5.7 mm.
    let rect = b.eval("(() => { const e = document.getElementById('p-r1'); e.scrollIntoView(); const r = e.getBoundingClientRect(); return [r.x, r.y, r.width, r.height]; })()");
    let r: Vec<f64> = rect.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    b.click(r[0] + 0.85 * r[2], r[1] + r[3] / 2.0);
    b.wait_for(
        &format!("{SETTLED} && Number(document.getElementById('p-r1').value) > 5 && +document.getElementById('chart').dataset.revision >= 2 && +document.getElementById('drawing').dataset.revision >= 2"),
        "the redraw after moving r1",
    );
    let r1: f64 = b
        .eval("document.getElementById('p-r1').value")
        .as_str()
        .unwrap()
        .parse()
        .unwrap();
    assert!((5.3..=6.0).contains(&r1), "r1 = {r1}");
    assert_ne!(b.eval(chart), chart0, "the take-up chart changed");
    assert_ne!(b.eval(table), table0, "max P in the summary changed");
    assert_ne!(
        b.eval(drawing),
        drawing0,
        "the mechanism was redrawn with the new eccentric"
    );
    assert_eq!(
        b.eval("document.getElementById('error').classList.contains('shown')"),
        json!(false)
    );
    let shot = b.screenshot("serve-mf7923d-after.png");
    eprintln!("browser test: screenshot saved to {}", shot.display());

    // An impossible setting typed into a number box: the page shows the
    // server's 422 message in its error box; Reset brings the model back.
    b.eval("(() => { document.getElementById('settings-box').open = true; const e = document.getElementById('p-l_ab'); e.scrollIntoView(); e.focus(); e.select(); })()");
    b.call("Input.insertText", json!({ "text": "5" }));
    b.wait_for(
        &format!("{SETTLED} && document.getElementById('error').classList.contains('shown')"),
        "the error box for l_ab = 5 mm",
    );
    let message = b.eval("document.getElementById('error').textContent");
    assert!(
        message.as_str().unwrap().contains("alpha0"),
        "the library's message: {message}"
    );
    for id in ["chart", "summary", "drawing"] {
        assert_eq!(
            b.eval(&format!("document.getElementById('{id}').classList.contains('stale')")),
            json!(true),
            "the last good {id} is greyed"
        );
    }
    b.screenshot("serve-mf7923d-error.png");
    let reset = b.eval("(() => { const e = document.getElementById('reset'); e.scrollIntoView(); const r = e.getBoundingClientRect(); return [r.x + r.width / 2, r.y + r.height / 2]; })()");
    b.click(reset[0].as_f64().unwrap(), reset[1].as_f64().unwrap());
    b.wait_for(
        &format!("{SETTLED} && !document.getElementById('error').classList.contains('shown')"),
        "the page to recover after Reset",
    );
    assert_eq!(b.eval("document.getElementById('p-r1').value"), json!("4"));

    // Animation on request.
    let anim = b.eval("(() => { const e = document.getElementById('animate'); e.scrollIntoView(); const r = e.getBoundingClientRect(); return [r.x + r.width / 2, r.y + r.height / 2]; })()");
    b.click(anim[0].as_f64().unwrap(), anim[1].as_f64().unwrap());
    b.wait_for(
        &format!("{SETTLED} && document.querySelector('#drawing svg animate') !== null"),
        "the animated mechanism",
    );
    drop(b);
    server.stop();
}
