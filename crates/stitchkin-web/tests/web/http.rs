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
