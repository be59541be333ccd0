//! The HTTP shell: a few worker threads take requests from one listening
//! socket and answer them with [`App::handle`].
//!
//! Bound to a loopback address (the default, 127.0.0.1), the server also
//! refuses requests whose `Host` is not this machine, so a web page
//! elsewhere cannot reach it through a DNS name that resolves here.

use std::net::SocketAddr;
use std::sync::Arc;
use std::thread::JoinHandle;

use stitchkin::error::{Error, IoError};
use tiny_http::{Header, Method, Request, Response};

use crate::api::{App, Reply};

/// A running server.
pub struct Server {
    addr: SocketAddr,
    http: Arc<tiny_http::Server>,
    workers: Vec<JoinHandle<()>>,
}

impl Server {
    /// Listens on `addr` (`127.0.0.1:0` picks a free port) and answers with
    /// `threads` workers (at least one).
    pub fn start(app: App, addr: &str, threads: usize) -> Result<Server, Error> {
        let http = tiny_http::Server::http(addr).map_err(|e| match e.downcast::<std::io::Error>() {
            Ok(io) => Error::Io(IoError::os(format!("listen on {addr}"), None, *io)),
            Err(e) => Error::Io(IoError::refused(format!("listen on {addr}"), None, e.to_string())),
        })?;
        let addr = http.server_addr().to_ip().ok_or_else(|| {
            Error::Io(IoError::refused(
                format!("listen on {addr}"),
                None,
                "it is not an IP address",
            ))
        })?;
        let http = Arc::new(http);
        let app = Arc::new(app);
        let loopback = addr.ip().is_loopback();
        let workers = (0..threads.max(1))
            .map(|_| {
                let (http, app) = (Arc::clone(&http), Arc::clone(&app));
                std::thread::spawn(move || {
                    // `recv` fails once the server is unblocked: stop then.
                    while let Ok(request) = http.recv() {
                        answer(&app, request, loopback);
                    }
                })
            })
            .collect();
        Ok(Server { addr, http, workers })
    }

    /// The address it listens on (with the port chosen).
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// The page's address.
    pub fn url(&self) -> String {
        format!("http://{}/", self.addr)
    }

    /// Blocks until the server stops (for `stitchkin serve`: until the
    /// process is interrupted).
    pub fn join(self) {
        for w in self.workers {
            let _ = w.join();
        }
    }

    /// Stops taking requests and waits for the workers.
    pub fn stop(self) {
        // Each call releases one worker waiting in `recv`.
        for _ in &self.workers {
            self.http.unblock();
        }
        self.join();
    }
}

/// Is `host` (a `Host` header, with or without port) this machine?
fn is_local_host(host: &str) -> bool {
    let name = if let Some(rest) = host.strip_prefix('[') {
        rest.split(']').next().unwrap_or("")
    } else {
        host.rsplit_once(':').map_or(host, |(h, _)| h)
    };
    matches!(name.to_ascii_lowercase().as_str(), "127.0.0.1" | "localhost" | "::1")
}

fn answer(app: &App, request: Request, loopback: bool) {
    let host = request
        .headers()
        .iter()
        .find(|h| h.field.equiv("Host"))
        .map(|h| h.value.as_str().to_string());
    let method = request.method().clone();
    let reply = match &host {
        Some(h) if loopback && !is_local_host(h) => Reply::error(
            403,
            format!("this server answers requests for this machine only, not for Host `{h}`"),
            Some("open the page at http://127.0.0.1:PORT/ (or http://localhost:PORT/)"),
        ),
        _ => app.handle(method.as_str(), request.url()),
    };
    if reply.status >= 400 {
        eprintln!("{} {} → {} {}", method, request.url(), reply.status, reply.text());
    }
    let body = if method == Method::Head { Vec::new() } else { reply.body };
    let header = |k: &str, v: &str| Header::from_bytes(k.as_bytes(), v.as_bytes()).expect("static header is valid");
    let mut response = Response::from_data(body)
        .with_status_code(reply.status)
        .with_header(header("Content-Type", reply.content_type))
        .with_header(header("Cache-Control", "no-store"))
        .with_header(header("X-Content-Type-Options", "nosniff"))
        .with_header(header(
            "Content-Security-Policy",
            "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data:; connect-src 'self'",
        ));
    if reply.status == 405 {
        response = response.with_header(header("Allow", "GET, HEAD"));
    }
    // A client that went away is not the server's problem.
    let _ = request.respond(response);
}

#[cfg(test)]
mod tests {
    use super::is_local_host;

    #[test]
    fn local_hosts() {
        for h in ["127.0.0.1:8080", "localhost:1", "LOCALHOST", "[::1]:80", "127.0.0.1"] {
            assert!(is_local_host(h), "{h}");
        }
        for h in ["evil.example:8080", "127.0.0.1.example", "10.0.0.1:80", "[::2]:80", ""] {
            assert!(!is_local_host(h), "{h}");
        }
    }
}
