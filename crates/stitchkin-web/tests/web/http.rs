//! The server over real HTTP on a loopback port.

use std::io::{Read, Write};
use std::net::TcpStream;

use stitchkin::model::Model;
use stitchkin_web::{App, Server};

pub fn start(preset: &str) -> Server {
    let model = Model::preset(preset).unwrap();
    let base = model.defaults();
    Server::start(App::new(model, base), "127.0.0.1:0", 2).unwrap()
}

/// Sends `request` as is and returns the status and the whole answer.
fn raw(server: &Server, request: &str) -> (u16, String) {
    let mut s = TcpStream::connect(server.addr()).unwrap();
    s.write_all(request.as_bytes()).unwrap();
    let mut answer = String::new();
    s.read_to_string(&mut answer).unwrap();
    let status = answer.split(' ').nth(1).and_then(|c| c.parse().ok()).unwrap_or(0);
    (status, answer)
}

fn get(server: &Server, path: &str, host: &str) -> (u16, String) {
    raw(
        server,
        &format!("GET {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"),
    )
}

#[test]
fn serves_the_page_and_api_on_loopback() {
    let server = start("needle876");
    assert!(server.addr().ip().is_loopback());
    assert_ne!(server.addr().port(), 0);
    let host = server.addr().to_string();
    let (status, page) = get(&server, "/", &host);
    assert_eq!(status, 200);
    assert!(page.contains("Content-Type: text/html"), "{page}");
    assert!(page.contains("Content-Security-Policy"));
    assert!(page.contains("<title>stitchkin</title>"));
    let (status, model) = get(&server, "/api/model", &format!("localhost:{}", server.addr().port()));
    assert_eq!(status, 200);
    assert!(model.contains("\"name\":\"needle876\""));
    // Several at once: the workers share the work.
    let handles: Vec<_> = (0..4)
        .map(|k| {
            let (addr, host) = (server.addr(), host.clone());
            std::thread::spawn(move || {
                let mut s = TcpStream::connect(addr).unwrap();
                write!(
                    s,
                    "GET /api/evaluate?step={} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n",
                    1 + k
                )
                .unwrap();
                let mut a = String::new();
                s.read_to_string(&mut a).unwrap();
                a
            })
        })
        .collect();
    for h in handles {
        let a = h.join().unwrap();
        assert!(a.starts_with("HTTP/1.1 200"), "{a}");
    }
    server.stop();
}

#[test]
fn refuses_foreign_hosts_other_methods_and_bad_queries() {
    let server = start("needle876");
    let host = server.addr().to_string();
    let (status, body) = get(&server, "/", "attacker.example");
    assert_eq!(status, 403, "{body}");
    assert!(body.contains("this machine only"));
    let (status, body) = raw(
        &server,
        &format!("DELETE /api/model HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"),
    );
    assert_eq!(status, 405);
    assert!(body.contains("Allow: GET, HEAD"), "{body}");
    let (status, body) = get(&server, "/api/evaluate?p.alpha=1e9", &host);
    assert_eq!(status, 400, "{body}");
    let (status, body) = raw(
        &server,
        &format!("HEAD / HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"),
    );
    assert_eq!(status, 200);
    assert!(!body.contains("<html"), "HEAD has no body");
    server.stop();
}

/// A POST of `body` to /api/models with these extra header lines.
fn post(server: &Server, headers: &str, body: &[u8]) -> (u16, String) {
    let host = server.addr().to_string();
    let head = format!(
        "POST /api/models?name=mine.toml HTTP/1.1\r\nHost: {host}\r\nContent-Type: application/toml\r\nContent-Length: {}\r\nConnection: close\r\n{headers}\r\n",
        body.len()
    );
    let mut s = TcpStream::connect(server.addr()).unwrap();
    s.write_all(head.as_bytes()).unwrap();
    // The server may answer before taking all of a body it refuses.
    let _ = s.write_all(body);
    let mut answer = Vec::new();
    let _ = s.read_to_end(&mut answer);
    let answer = String::from_utf8_lossy(&answer).into_owned();
    let status = answer.split(' ').nth(1).and_then(|c| c.parse().ok()).unwrap_or(0);
    (status, answer)
}

#[test]
fn a_model_file_is_loaded_over_http_within_its_limits() {
    let server = start("needle876");
    let host = server.addr().to_string();
    let text = stitchkin::presets::find("takeup-lever").unwrap().toml;
    let origin = format!("Origin: http://{host}\r\n");
    let (status, answer) = post(&server, &origin, text.as_bytes());
    assert_eq!(status, 200, "{answer}");
    let key = answer
        .split("\"model\":\"")
        .nth(1)
        .and_then(|r| r.split('"').next())
        .unwrap()
        .to_string();
    let (status, model) = get(&server, &format!("/api/model?model={key}"), &host);
    assert_eq!(status, 200, "{model}");
    assert!(model.contains("\"name\":\"takeup-lever\""), "{model}");
    // A page elsewhere cannot load files into this server.
    let (status, answer) = post(&server, "Origin: http://attacker.example\r\n", text.as_bytes());
    assert_eq!(status, 403, "{answer}");
    // Too large: refused from its Content-Length, the limit in the message.
    let big = vec![b'#'; stitchkin_web::api::MAX_FILE_BYTES + 10];
    let (status, answer) = post(&server, "", &big);
    assert_eq!(status, 413, "{answer}");
    assert!(answer.contains("256 kB"), "{answer}");
    // Only /api/models takes a POST, and says so.
    let (status, answer) = raw(
        &server,
        &format!("PUT /api/models HTTP/1.1\r\nHost: {host}\r\nContent-Length: 0\r\nConnection: close\r\n\r\n"),
    );
    assert_eq!(status, 405);
    assert!(answer.contains("Allow: GET, HEAD, POST"), "{answer}");
    server.stop();
}

/// A POST of `body` as a measured curve with these extra header lines.
fn post_curve(server: &Server, headers: &str, body: &[u8]) -> (u16, String) {
    let host = server.addr().to_string();
    let head = format!(
        "POST /api/measured?name=bench.csv HTTP/1.1\r\nHost: {host}\r\nContent-Type: text/csv\r\nContent-Length: {}\r\nConnection: close\r\n{headers}\r\n",
        body.len()
    );
    let mut s = TcpStream::connect(server.addr()).unwrap();
    s.write_all(head.as_bytes()).unwrap();
    let _ = s.write_all(body);
    let mut answer = Vec::new();
    let _ = s.read_to_end(&mut answer);
    let answer = String::from_utf8_lossy(&answer).into_owned();
    let status = answer.split(' ').nth(1).and_then(|c| c.parse().ok()).unwrap_or(0);
    (status, answer)
}

#[test]
fn a_measured_curve_is_sent_over_http_within_its_limits() {
    let server = start("altin504");
    let host = server.addr().to_string();
    let text = include_str!("../../../../examples/seed004-bench-lower.csv");
    let (status, answer) = post_curve(&server, &format!("Origin: http://{host}\r\n"), text.as_bytes());
    assert_eq!(status, 200, "{answer}");
    let key = answer
        .split("\"key\":\"")
        .nth(1)
        .and_then(|r| r.split('"').next())
        .unwrap()
        .to_string();
    let (status, evaluation) = get(&server, &format!("/api/evaluate?measured={key}&step=2"), &host);
    assert_eq!(status, 200, "{evaluation}");
    assert!(evaluation.contains("Polyakov (2022) §3.4"), "the error bars");
    // Not from a page elsewhere, not larger than the limit (from its
    // Content-Length, the limit in the message), and only by POST.
    let (status, answer) = post_curve(&server, "Origin: http://attacker.example\r\n", text.as_bytes());
    assert_eq!(status, 403, "{answer}");
    let big = vec![b'#'; stitchkin_web::api::MAX_CURVE_BYTES + 10];
    let (status, answer) = post_curve(&server, "", &big);
    assert_eq!(status, 413, "{answer}");
    assert!(
        answer.contains("measured curve") && answer.contains("256 kB"),
        "{answer}"
    );
    let (status, answer) = get(&server, "/api/measured", &host);
    assert_eq!(status, 405, "{answer}");
    assert!(answer.contains("Allow: POST"), "{answer}");
    server.stop();
}
