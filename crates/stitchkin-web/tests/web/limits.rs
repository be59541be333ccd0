//! The server's limits over real HTTP, with small timeouts and caps so the
//! tests run fast. Time bounds are generous (a loaded two-core machine):
//! they check that something ends, not how soon.

use std::io::{ErrorKind, Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use stitchkin::model::Model;
use stitchkin_web::{App, Server, ServerConfig};

/// Longer than any timeout of the servers here, and than a computation on
/// a busy machine: a read that waits this long has hung.
const HUNG: Duration = Duration::from_secs(20);

fn start(config: ServerConfig) -> Server {
    let model = Model::preset("needle876").unwrap();
    let base = model.defaults();
    Server::start_with(App::new(model, base), "127.0.0.1:0", &config).unwrap()
}

fn connect(server: &Server) -> TcpStream {
    let s = TcpStream::connect(server.addr()).unwrap();
    s.set_read_timeout(Some(HUNG)).unwrap();
    s
}

/// Everything the server sends until it closes the connection (a reset
/// ends it too); `None` if it still says nothing after [`HUNG`].
fn read_all(s: &mut TcpStream) -> Option<String> {
    let mut answer = Vec::new();
    match s.read_to_end(&mut answer) {
        Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => None,
        _ => Some(String::from_utf8_lossy(&answer).into_owned()),
    }
}

fn status(answer: &str) -> u16 {
    answer.split(' ').nth(1).and_then(|c| c.parse().ok()).unwrap_or(0)
}

fn get(server: &Server, path: &str) -> String {
    let mut s = connect(server);
    let host = server.addr();
    s.write_all(format!("GET {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n").as_bytes())
        .unwrap();
    read_all(&mut s).expect("the server answers")
}

/// Asks `/api/model` until it is answered 200 (the server may still be
/// closing other connections); panics after [`HUNG`].
fn answers_again(server: &Server) {
    let began = Instant::now();
    loop {
        let answer = get(server, "/api/model");
        if status(&answer) == 200 {
            return;
        }
        assert!(began.elapsed() < HUNG, "still not answering: {answer}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn small() -> ServerConfig {
    ServerConfig {
        threads: 1,
        max_connections: 4,
        header_timeout_ms: 300,
        write_timeout_ms: 300,
        ..ServerConfig::default()
    }
}

#[test]
fn a_request_with_bare_line_feeds_is_answered_or_closed() {
    let server = start(small());
    let mut s = connect(&server);
    write!(
        s,
        "GET /api/model HTTP/1.1\nHost: {}\nConnection: close\n\n",
        server.addr()
    )
    .unwrap();
    let answer = read_all(&mut s).expect("an answer or a close, not a hang");
    assert!(answer.is_empty() || [200, 400].contains(&status(&answer)), "{answer}");
    answers_again(&server);
    server.stop();
}

#[test]
fn idle_and_half_sent_connections_are_closed_after_the_timeout() {
    let server = start(small());
    let mut idle = connect(&server);
    let mut half = connect(&server);
    write!(half, "GET /api/model HTTP/1.1\r\nHost: {}\r\n", server.addr()).unwrap();
    // After one answer, a kept-alive connection that asks nothing more.
    let mut kept = connect(&server);
    write!(kept, "GET /api/model HTTP/1.1\r\nHost: {}\r\n\r\n", server.addr()).unwrap();
    for s in [&mut idle, &mut half, &mut kept] {
        let answer = read_all(s).expect("closed by the server, not held");
        assert!(answer.is_empty() || status(&answer) == 200, "{answer}");
    }
    server.stop();
}

#[test]
fn at_the_cap_the_oldest_idle_connection_makes_room() {
    let server = start(ServerConfig {
        max_connections: 2,
        header_timeout_ms: 60_000,
        ..small()
    });
    let mut held: Vec<TcpStream> = (0..2).map(|_| connect(&server)).collect();
    // A new connection has a second to ask before it may make room.
    let answer = get(&server, "/api/model");
    assert_eq!(status(&answer), 503, "{answer}");
    std::thread::sleep(Duration::from_millis(1200));
    // Both connections are open and have asked nothing for longer: a new
    // one is served at once, in the place of the older.
    let answer = get(&server, "/api/model");
    assert_eq!(status(&answer), 200, "{answer}");
    assert_eq!(
        read_all(&mut held[0]).as_deref(),
        Some(""),
        "the oldest idle one is closed"
    );
    // The younger is still open (a read waits).
    held[1].set_read_timeout(Some(Duration::from_millis(200))).unwrap();
    let mut byte = [0u8; 1];
    let still_open =
        matches!(held[1].read(&mut byte), Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut));
    assert!(still_open, "the younger idle connection stays open");
    server.stop();
}

#[test]
fn connections_beyond_the_cap_get_503_when_none_is_idle_and_answers_after() {
    let server = start(ServerConfig {
        max_connections: 2,
        write_timeout_ms: 2_000,
        ..small()
    });
    // Two clients that ask for the page many times over and read nothing:
    // the answers fill the sockets' buffers, and both connections are busy
    // sending until the write timeout.
    let one = format!("GET / HTTP/1.1\r\nHost: {}\r\n\r\n", server.addr());
    let greedy: Vec<TcpStream> = (0..2)
        .map(|_| {
            let mut s = connect(&server);
            let _ = s.write_all(one.repeat(2000).as_bytes());
            s
        })
        .collect();
    // Their requests are on their way (not idle) once the server has read
    // some; it may not have when the next connection comes.
    std::thread::sleep(Duration::from_millis(300));
    let began = Instant::now();
    let answer = loop {
        let answer = get(&server, "/api/model");
        if status(&answer) == 503 {
            break answer;
        }
        assert!(began.elapsed() < HUNG, "no 503 while both connections send: {answer}");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(
        answer.contains("Retry-After") && answer.contains("connections open"),
        "{answer}"
    );
    answers_again(&server);
    drop(greedy);
    server.stop();
}

#[test]
fn long_addresses_get_414_or_431_without_their_text() {
    let server = start(small());
    let run = "a".repeat(100);
    for path in [
        format!("/{}", "a".repeat(20_000)),
        format!("/api/evaluate?p.{}=1", "a".repeat(20_000)),
    ] {
        let answer = get(&server, &path);
        assert_eq!(status(&answer), 414, "{}", &answer[..answer.len().min(300)]);
        assert!(!answer.contains(&run) && answer.len() < 2000, "{answer}");
    }
    // A request line longer than a whole head may be: refused with 431
    // (or cut off while the client is still sending it), never echoed.
    let mut s = connect(&server);
    let huge = format!(
        "GET /{} HTTP/1.1\r\nHost: {}\r\n\r\n",
        "a".repeat(1 << 20),
        server.addr()
    );
    let _ = s.write_all(huge.as_bytes());
    let answer = read_all(&mut s).unwrap_or_default();
    assert!(answer.is_empty() || status(&answer) == 431, "{answer}");
    assert!(!answer.contains(&run));
    answers_again(&server);
    server.stop();
}

#[test]
fn a_client_that_reads_no_answer_is_dropped() {
    let server = start(ServerConfig {
        max_connections: 1,
        ..small()
    });
    // Many pipelined requests for the page and no read: the answers fill
    // the socket's buffers and the server's writes stall.
    let mut greedy = connect(&server);
    let one = format!("GET / HTTP/1.1\r\nHost: {}\r\n\r\n", server.addr());
    let _ = greedy.write_all(one.repeat(2000).as_bytes());
    // Until the write timeout the one connection is taken; then it is
    // dropped and the server answers others again.
    answers_again(&server);
    server.stop();
}
