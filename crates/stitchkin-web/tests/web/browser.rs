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
use stitchkin_web::Server;
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
        // One profile per browser: the tests of this binary run at once.
        static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let k = NEXT.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        let profile = TempDir(std::env::temp_dir().join(format!("stitchkin-chromium-{}-{k}", std::process::id())));
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

/// The browser to drive, or none (said loudly; a failure where CI requires
/// one).
fn chromium_or_skip() -> Option<PathBuf> {
    let exe = chromium();
    if exe.is_none() {
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
    }
    exe
}

#[test]
fn moving_a_slider_redraws_the_take_up_summary_and_mechanism() {
    let Some(exe) = chromium_or_skip() else { return };
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
    // Every parameter with a range but the stitch's m and t (r1, l_o2b, z,
    // dphi, the thread's EA, breaking force, regulator and clamp holds, …).
    let model = stitchkin::model::Model::preset("mf7923d").unwrap();
    let stitch_inputs = [model.stitch_param("m"), model.stitch_param("t")];
    let ranged = model
        .params()
        .iter()
        .filter(|p| !p.is_derived() && p.range.is_some() && !stitch_inputs.contains(&Some(p.name.as_str())))
        .count();
    assert!(ranged >= 5, "{ranged}");
    assert_eq!(
        b.eval("document.querySelectorAll('#adjustable input[type=range]').length"),
        json!(ranged),
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

impl Browser {
    /// Gives the file input `id` the file at `path`, as choosing it does.
    fn choose_file(&mut self, id: &str, path: &std::path::Path) {
        let doc = self.call("DOM.getDocument", json!({}));
        let node = self.call(
            "DOM.querySelector",
            json!({ "nodeId": doc["root"]["nodeId"], "selector": format!("#{id}") }),
        );
        self.call(
            "DOM.setFileInputFiles",
            json!({ "nodeId": node["nodeId"], "files": [path.display().to_string()] }),
        );
    }

    /// Opens `url` afresh (as a shared link is opened) and waits for the
    /// page to settle.
    fn open(&mut self, url: &str) {
        self.call("Page.navigate", json!({ "url": "about:blank" }));
        self.wait_for("location.href === 'about:blank'", "a blank page");
        self.call("Page.navigate", json!({ "url": url }));
        self.wait_for(SETTLED, &format!("the page at {url}"));
    }
}

/// Text boxes of the page's drawing and charts that overlap or leave the
/// picture (SVG units): none is the aim.
const CROWDED: &str = r#"(() => {
  const out = [];
  const svg = document.querySelector('#drawing svg');
  const boxes = [...svg.querySelectorAll('g[class^="label"] text')].map((t) => {
    const r = t.getBoundingClientRect();
    return { name: t.textContent, x0: r.left, y0: r.top, x1: r.right, y1: r.bottom };
  });
  for (let i = 0; i < boxes.length; i++) for (let j = i + 1; j < boxes.length; j++) {
    const a = boxes[i], b = boxes[j];
    const w = Math.min(a.x1, b.x1) - Math.max(a.x0, b.x0), h = Math.min(a.y1, b.y1) - Math.max(a.y0, b.y0);
    // Glyph boxes include the line's ascent and descent: a sliver is not an overlap.
    if (w > 1 && h > 2) out.push('labels ' + a.name + ' and ' + b.name + ' overlap');
  }
  for (const chart of document.querySelectorAll('#chart svg, #tension svg')) {
    const width = chart.viewBox.baseVal.width;
    for (const t of chart.querySelectorAll('text.title, text.subtitle')) {
      const b = t.getBBox();
      if (b.x + b.width > width + 0.5) out.push('`' + t.textContent.slice(0, 40) + '…` ends at ' + (b.x + b.width).toFixed(0) + ' of ' + width);
    }
  }
  return out;
})()"#;

#[test]
fn a_chosen_preset_a_moved_slider_and_a_loaded_file_come_back_from_the_address() {
    let Some(exe) = chromium_or_skip() else { return };
    let server = super::http::start("mf7923d");
    let mut b = Browser::launch(&exe);
    b.open_tab();
    b.open(&server.url());
    // The address names the model at once; the menu lists every preset
    // with its title.
    b.wait_for("location.search === '?model=mf7923d'", "the model in the address");
    let options = b.eval("[...document.getElementById('model').options].map((o) => [o.value, o.textContent])");
    for p in stitchkin::presets::ALL {
        let title = stitchkin::model::Model::preset(p.name)
            .unwrap()
            .title()
            .unwrap()
            .to_string();
        assert!(
            options
                .as_array()
                .unwrap()
                .iter()
                .any(|o| o[0] == p.name && o[1].as_str().unwrap().contains(&title)),
            "{} with its title in {options}",
            p.name
        );
    }
    // A slider's plain label with its unit; on hover what the part is.
    let model = stitchkin::model::Model::preset("mf7923d").unwrap();
    let r1 = &model.params()[model.param_index("r1").unwrap()];
    let (label, what) = (r1.label.clone().unwrap(), r1.what.clone().unwrap());
    let shown = b.eval("document.querySelector('label[for=\"p-r1\"] .name').textContent");
    assert!(shown.as_str().unwrap().starts_with(&format!("{label}, mm")), "{shown}");
    let hover = b.eval("document.getElementById('p-r1').closest('.ctl').title");
    let hover = hover.as_str().unwrap();
    assert!(hover.contains("machine setting") && hover.contains(&what), "{hover}");
    // The MF-7923D's drawing and charts: no label over another, no title
    // past the picture's edge.
    assert_eq!(b.eval(CROWDED), json!([]), "crowded or clipped text");

    // Choose the needle mechanism from the menu: its stroke is shown.
    b.eval("(() => { const s = document.getElementById('model'); s.focus(); s.value = 'needle876'; s.dispatchEvent(new Event('change')); })()");
    let readout = "document.querySelector('.readout[data-name=\"needle_y.stroke\"] .rv').textContent";
    b.wait_for(
        &format!(
            "{SETTLED} && document.body.dataset.model === 'needle876' && document.getElementById('p-alpha') !== null && document.querySelector('.readout[data-name=\"needle_y.stroke\"]') !== null && location.search === '?model=needle876'"
        ),
        "needle876 with its stroke readout",
    );
    let stroke0 = b.eval(readout);
    assert_eq!(b.eval("document.getElementById('p-alpha').value"), json!("0"));
    assert_eq!(
        b.eval("document.getElementById('p-r1')"),
        json!(null),
        "the MF-7923D's sliders are gone"
    );
    b.screenshot("serve-needle876.png");

    // Move α to about 70 % of its 0…45° range.
    let rect = b.eval("(() => { const e = document.getElementById('p-alpha'); e.scrollIntoView(); const r = e.getBoundingClientRect(); return [r.x, r.y, r.width, r.height]; })()");
    let r: Vec<f64> = rect.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    b.click(r[0] + 0.7 * r[2], r[1] + r[3] / 2.0);
    b.wait_for(
        &format!(
            "{SETTLED} && Number(document.getElementById('p-alpha').value) > 20 && {readout} !== {stroke0} && location.search.includes('p.alpha=')"
        ),
        "the stroke after moving α, and α in the address",
    );
    let alpha: f64 = b
        .eval("document.getElementById('p-alpha').value")
        .as_str()
        .unwrap()
        .parse()
        .unwrap();
    let stroke = b.eval(readout);
    let href = b.eval("location.href").as_str().unwrap().to_string();
    assert!(
        href.contains("model=needle876") && href.contains(&format!("p.alpha={alpha}")),
        "{href}"
    );
    // The readout is the library's stroke at that α.
    let model = stitchkin::model::Model::preset("needle876").unwrap();
    let mut params = model.defaults();
    model.set(&mut params, "alpha", alpha).unwrap();
    let axis = stitchkin::study::stroke::Axis::parse(&model, "y").unwrap();
    let g = model.moving_point_slot("G").unwrap();
    let expected = stitchkin::study::stroke::stroke(&model, &params, g, &axis, 1.0)
        .unwrap()
        .stroke_mm;
    assert_eq!(stroke, json!(format!("{expected:.2}")), "α = {alpha}");

    // Reload from the address: the same model, α and stroke.
    b.open(&href);
    b.wait_for("document.body.dataset.model === 'needle876'", "needle876 again");
    assert_eq!(b.eval("document.getElementById('model').value"), json!("needle876"));
    assert_eq!(
        b.eval("document.getElementById('p-alpha').value"),
        json!(alpha.to_string())
    );
    assert_eq!(b.eval(readout), stroke, "the stroke at α = {alpha}");
    assert_eq!(
        b.eval("document.getElementById('notice').classList.contains('shown')"),
        json!(false)
    );
    assert_eq!(b.eval("location.href"), json!(href), "the address as it was");
    b.screenshot("serve-needle876-reloaded.png");

    addresses_with_what_the_page_cannot_use(&mut b, &server, &stroke0);
    model_files_from_the_file_picker(&mut b);
    drop(b);
    server.stop();
}

/// An address with a value out of range, an unknown view and key: each
/// said and ignored, the rest of the page as it should be (needle876 at
/// α = 0 shows `stroke0`).
fn addresses_with_what_the_page_cannot_use(b: &mut Browser, server: &Server, stroke0: &Value) {
    let readout = "document.querySelector('.readout[data-name=\"needle_y.stroke\"] .rv').textContent";
    b.open(&format!(
        "{}?model=needle876&p.alpha=99&view=sideways&zoom=2",
        server.url()
    ));
    let notice = b.eval("document.getElementById('notice').textContent");
    let notice = notice.as_str().unwrap();
    for says in [
        "p.alpha = 99 deg is outside 0…45 deg",
        "view = “sideways”",
        "“zoom” is not a setting",
    ] {
        assert!(notice.contains(says), "`{says}` in the notice: {notice}");
    }
    assert_eq!(b.eval("document.getElementById('p-alpha').value"), json!("0"));
    assert_eq!(&b.eval(readout), stroke0);
    assert_eq!(
        b.eval("document.getElementById('error').classList.contains('shown')"),
        json!(false)
    );
}

/// A model file from the file picker: a bad one shows the library's
/// message with its place; a good one is drawn and kept by its key.
fn model_files_from_the_file_picker(b: &mut Browser) {
    let dir = TempDir(std::env::temp_dir().join(format!("stitchkin-files-{}", std::process::id())));
    std::fs::create_dir_all(&dir.0).unwrap();
    let text = stitchkin::presets::find("takeup-lever").unwrap().toml;
    let broken = dir.0.join("broken.toml");
    std::fs::write(
        &broken,
        text.replacen(
            "[parameters]",
            "[parameters]\nzz = { value = 1, unit = \"furlong\" }",
            1,
        ),
    )
    .unwrap();
    b.choose_file("file-input", &broken);
    b.wait_for(
        &format!("{SETTLED} && document.getElementById('error').classList.contains('shown')"),
        "the error box for broken.toml",
    );
    let error = b.eval("document.getElementById('error').textContent");
    let error = error.as_str().unwrap();
    let expected =
        stitchkin::model::Model::from_toml_str(&std::fs::read_to_string(&broken).unwrap(), "broken.toml").unwrap_err();
    assert!(
        error.contains("broken.toml:") && error.contains(&expected.message),
        "{error}"
    );
    assert!(error.contains("furlong"), "the file's line under the message: {error}");
    assert_eq!(
        b.eval("document.body.dataset.model"),
        json!("needle876"),
        "the page keeps its model"
    );
    b.screenshot("serve-file-error.png");
    let good = dir.0.join("lever.toml");
    std::fs::write(&good, text).unwrap();
    b.choose_file("file-input", &good);
    b.wait_for(
        &format!("{SETTLED} && document.body.dataset.model.startsWith('file:') && !document.getElementById('error').classList.contains('shown')"),
        "the loaded file drawn",
    );
    let key = b.eval("document.body.dataset.model").as_str().unwrap().to_string();
    let note = b.eval("document.getElementById('file-note').textContent");
    assert!(note.as_str().unwrap().contains("cannot be in the address"), "{note}");
    let href = b.eval("location.href").as_str().unwrap().to_string();
    assert!(href.contains(&format!("model={}", key.replace(':', "%3A"))), "{href}");
    b.open(&href);
    b.wait_for(
        &format!("document.body.dataset.model === '{key}'"),
        "the loaded file from the address",
    );
    assert!(
        b.eval("document.getElementById('title').textContent")
            .as_str()
            .unwrap()
            .contains("takeup-lever")
    );
    b.screenshot("serve-file.png");
}

/// The repository's example of bench readings, `examples/NAME`.
fn example(name: &str) -> PathBuf {
    // Canonical: Chromium does not read a chosen file through `..`.
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    path.canonicalize()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn a_measured_take_up_is_drawn_with_its_error_bars_on_every_slider_move() {
    let Some(exe) = chromium_or_skip() else { return };
    let server = super::http::start("mf7923d");
    let mut b = Browser::launch(&exe);
    b.open_tab();
    b.open(&server.url());
    let bars = "document.querySelectorAll('#chart svg polygon.area title').length";
    let cited = "[...document.querySelectorAll('#chart svg polygon.area title')].filter((t) => t.textContent.includes('Polyakov (2022) §3.4')).length";
    let note = "document.getElementById('measured-note').textContent";
    assert_eq!(b.eval(bars), json!(0), "no error bars before a curve is loaded");
    assert_eq!(
        b.eval("document.getElementById('measured-clear').disabled"),
        json!(true)
    );

    // Ten readings every 10° of needle 1 at B (the machine set 3 mm lower
    // on z and 5° later): the mean curve and an error bar at each φ read.
    b.choose_file("measured-input", &example("mf7923d-bench-n1.csv"));
    b.wait_for(
        &format!("{SETTLED} && document.body.dataset.measured.startsWith('measured:') && {cited} >= 36"),
        "the measured curve with its error bars",
    );
    assert_eq!(
        b.eval(cited),
        b.eval(bars),
        "every bar cites seed 004 by author and year"
    );
    let svg = b.eval("document.querySelector('#chart svg').outerHTML");
    assert!(
        svg.as_str().unwrap().contains("n1 P measured"),
        "the mean curve in the legend"
    );
    let said = b.eval(note).as_str().unwrap().to_string();
    for part in [
        "mf7923d-bench-n1.csv",
        "36 points",
        "10 readings per φ",
        "mm (95 %",
        "set beside n1 (at B)",
        "within the interval at",
        "score",
    ] {
        assert!(said.contains(part), "`{part}` in the line: {said}");
    }
    assert_eq!(b.eval("document.getElementById('measured-thread').value"), json!(""));
    assert_eq!(
        b.eval("[...document.getElementById('measured-thread').options].map((o) => o.textContent)"),
        json!(["from the file (n1)", "n1", "n2", "n3"])
    );
    b.screenshot("serve-measured.png");

    // The sliders move the model; the curve and its bars stay, the match follows.
    let revision = b
        .eval("+document.getElementById('chart').dataset.revision")
        .as_f64()
        .unwrap();
    let rect = b.eval("(() => { const e = document.getElementById('p-r1'); e.scrollIntoView(); const r = e.getBoundingClientRect(); return [r.x, r.y, r.width, r.height]; })()");
    let r: Vec<f64> = rect.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    b.click(r[0] + 0.6 * r[2], r[1] + r[3] / 2.0);
    b.wait_for(
        &format!("{SETTLED} && +document.getElementById('chart').dataset.revision > {revision} && Number(document.getElementById('p-r1').value) > 4.5"),
        "the redraw after moving r1",
    );
    assert!(
        b.eval(cited).as_u64().unwrap() >= 36,
        "the error bars after the slider moved"
    );
    assert_ne!(b.eval(note).as_str().unwrap(), said, "the match follows the model");

    // Another thread from the menu.
    b.eval("(() => { const s = document.getElementById('measured-thread'); s.value = 'n2'; s.dispatchEvent(new Event('change')); })()");
    b.wait_for(
        &format!("{SETTLED} && document.getElementById('measured-note').textContent.includes('set beside n2')"),
        "the curve beside n2",
    );

    // A file that does not read: the library's message with its line in the
    // red box, the curve loaded before kept.
    let dir = TempDir(std::env::temp_dir().join(format!("stitchkin-measured-{}", std::process::id())));
    std::fs::create_dir_all(&dir.0).unwrap();
    let text = std::fs::read_to_string(example("mf7923d-bench-n1.csv")).unwrap();
    let broken = dir.0.join("bench-typo.csv");
    std::fs::write(&broken, text.replacen("0.10,0.10,0.10", "0.10,O.10,0.10", 1)).unwrap();
    let key = b.eval("document.body.dataset.measured");
    b.choose_file("measured-input", &broken);
    b.wait_for(
        &format!("{SETTLED} && document.getElementById('error').classList.contains('shown')"),
        "the error box for bench-typo.csv",
    );
    let error = b.eval("document.getElementById('error').textContent");
    let error = error.as_str().unwrap();
    assert!(
        error.contains("bench-typo.csv:10:") && error.contains("O.10"),
        "{error}"
    );
    assert!(b.eval(note).as_str().unwrap().contains("bench-typo.csv was not read"));
    assert_eq!(
        b.eval("document.body.dataset.measured"),
        key,
        "the curve loaded before stays"
    );
    b.screenshot("serve-measured-error.png");

    // Seed 004's lower-looper readings name a thread the MF-7923D lacks:
    // the message says which it compares, and the menu offers them.
    b.choose_file("measured-input", &example("seed004-bench-lower.csv"));
    b.wait_for(
        &format!("{SETTLED} && document.getElementById('error').textContent.includes('`lower`')"),
        "the message for a thread the model lacks",
    );
    assert!(
        b.eval("document.getElementById('error').textContent")
            .as_str()
            .unwrap()
            .contains("n1, n2, n3")
    );
    b.eval("(() => { const s = document.getElementById('measured-thread'); s.value = 'n3'; s.dispatchEvent(new Event('change')); })()");
    b.wait_for(
        &format!("{SETTLED} && !document.getElementById('error').classList.contains('shown') && document.getElementById('measured-note').textContent.includes('set beside n3') && {cited} > 0"),
        "seed 004's curve beside n3",
    );

    // Clear: the model alone again.
    b.eval("document.getElementById('measured-clear').click()");
    b.wait_for(
        &format!("{SETTLED} && document.body.dataset.measured === '' && {bars} === 0"),
        "the chart without the measured curve",
    );
    assert_eq!(b.eval("document.getElementById('measured-note').hidden"), json!(true));
    drop(b);
    server.stop();
}

/// Every preset's drawing in each of its views at four φ, measured in the
/// browser with its own fonts: no label covers another.
#[test]
fn no_label_covers_another_in_any_preset_drawing() {
    let Some(exe) = chromium_or_skip() else { return };
    let server = super::http::start("mf7923d");
    let mut b = Browser::launch(&exe);
    b.open_tab();
    b.open(&server.url());
    let names: Vec<&str> = stitchkin::presets::ALL.iter().map(|p| p.name).collect();
    let found = b.eval(&format!(
        r#"(async () => {{
  const out = [];
  let drawn = 0;
  const box = document.createElement('div');
  box.style.cssText = 'position:absolute; left:-3000px; top:0; width:900px';
  document.body.append(box);
  for (const model of {names}) {{
    const m = await (await fetch('/api/model?model=' + model)).json();
    for (const view of m.views.map((v) => v.name)) for (const phi of [0, 90, 180, 270]) {{
      const res = await fetch('/api/drawing?model=' + model + '&view=' + view + '&phi=' + phi);
      if (!res.ok) {{ out.push(model + ' ' + view + ' ' + phi + ': ' + res.status); continue; }}
      box.innerHTML = await res.text();
      drawn++;
      const boxes = [...box.querySelectorAll('g[class^="label"] text')].map((t) => {{
        const r = t.getBoundingClientRect();
        return {{ name: t.textContent, x0: r.left, y0: r.top, x1: r.right, y1: r.bottom }};
      }});
      for (let i = 0; i < boxes.length; i++) for (let j = i + 1; j < boxes.length; j++) {{
        const a = boxes[i], c = boxes[j];
        const w = Math.min(a.x1, c.x1) - Math.max(a.x0, c.x0), h = Math.min(a.y1, c.y1) - Math.max(a.y0, c.y0);
        if (w > 1 && h > 2) out.push(model + ' ' + view + ' φ = ' + phi + ': ' + a.name + ' and ' + c.name);
      }}
    }}
  }}
  box.remove();
  return {{ drawn, out }};
}})()"#,
        names = json!(names)
    ));
    assert!(
        found["drawn"].as_u64().unwrap() >= 4 * 2 * names.len() as u64,
        "{found}"
    );
    assert_eq!(found["out"], json!([]), "labels that cover another");
    drop(b);
    server.stop();
}
