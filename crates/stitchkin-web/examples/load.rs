//! A load test for `stitchkin serve`: clients asking one URL over and over,
//! each on its own keep-alive connection, and what the server made of it.
//!
//! ```sh
//! stitchkin serve --port 8080 &
//! cargo run --release -p stitchkin-web --example load -- --clients 32 --seconds 10 http://127.0.0.1:8080/api/evaluate
//! ```
//!
//! Prints the answers per second, the latency p50/p99 in ms, and the
//! errors (refused or broken connections, and answers other than 200).
//!
//! Options:
//! - `--clients N` (1): connections asking at the same time.
//! - `--seconds S` (10): how long each client asks.
//! - `--requests N` (none): each client stops after N answers instead
//!   (`--clients 1000 --requests 1` is a burst of 1,000 requests at once).
//! - `--idle N` (0): N more connections opened before the clients start
//!   that send nothing and stay open until the end, to see that the server
//!   keeps answering the others (or closes them after its timeout).
//! - `--new-connection`: a new connection for every request.

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::ExitCode;
use std::sync::{Arc, Barrier};
use std::time::{Duration, Instant};

struct Options {
    clients: usize,
    seconds: f64,
    requests: Option<usize>,
    idle: usize,
    new_connection: bool,
    /// `host:port`
    authority: String,
    /// Path and query.
    target: String,
}

fn parse_args() -> Result<Options, String> {
    let mut o = Options {
        clients: 1,
        seconds: 10.0,
        requests: None,
        idle: 0,
        new_connection: false,
        authority: String::new(),
        target: String::new(),
    };
    let mut url = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = |name: &str| args.next().ok_or_else(|| format!("{name} needs a value"));
        match a.as_str() {
            "--clients" => o.clients = number(&value("--clients")?)?,
            "--seconds" => o.seconds = number(&value("--seconds")?)?,
            "--requests" => o.requests = Some(number(&value("--requests")?)?),
            "--idle" => o.idle = number(&value("--idle")?)?,
            "--new-connection" => o.new_connection = true,
            _ if a.starts_with("http://") => url = Some(a),
            _ => return Err(format!("unknown argument `{a}`")),
        }
    }
    let url = url.ok_or("give the URL to ask, e.g. http://127.0.0.1:8080/api/evaluate")?;
    let rest = url.trim_start_matches("http://");
    let (authority, target) = rest.split_at(rest.find('/').unwrap_or(rest.len()));
    o.authority = authority.to_string();
    o.target = if target.is_empty() { "/".into() } else { target.into() };
    o.clients = o.clients.max(1);
    Ok(o)
}

fn number<T: std::str::FromStr>(s: &str) -> Result<T, String> {
    s.parse().map_err(|_| format!("`{s}` is not a number"))
}

/// What one client saw: the latency of each 200 answer, and the errors
/// by kind.
#[derive(Default)]
struct Tally {
    latencies_us: Vec<u64>,
    errors: BTreeMap<String, usize>,
}

impl Tally {
    fn error(&mut self, e: String) {
        *self.errors.entry(e).or_default() += 1;
    }
}

/// Reads one answer: its status, and whether the server closes the
/// connection after it.
fn read_answer(r: &mut BufReader<TcpStream>) -> Result<(u16, bool), String> {
    let mut line = String::new();
    r.read_line(&mut line)
        .map_err(|e| format!("reading the status: {}", e.kind()))?;
    if line.is_empty() {
        return Err("the server closed the connection".into());
    }
    let status = line.split(' ').nth(1).and_then(|c| c.parse().ok()).unwrap_or(0);
    let (mut length, mut close, mut chunked) = (None, false, false);
    loop {
        line.clear();
        r.read_line(&mut line)
            .map_err(|e| format!("reading a header: {}", e.kind()))?;
        let l = line.trim_end().to_ascii_lowercase();
        if l.is_empty() {
            break;
        }
        if let Some(v) = l.strip_prefix("content-length:") {
            length = v.trim().parse::<u64>().ok();
        }
        if l.starts_with("connection:") && l.contains("close") {
            close = true;
        }
        if l.starts_with("transfer-encoding:") && l.contains("chunked") {
            chunked = true;
        }
    }
    match length {
        _ if chunked => read_chunks(r)?,
        Some(n) => {
            std::io::copy(&mut r.by_ref().take(n), &mut std::io::sink()).map_err(|e| format!("body: {e}"))?;
        }
        None => {
            std::io::copy(r, &mut std::io::sink()).map_err(|e| format!("body: {e}"))?;
            close = true;
        }
    }
    Ok((status, close))
}

/// Reads a chunked body to its end.
fn read_chunks(r: &mut BufReader<TcpStream>) -> Result<(), String> {
    let mut line = String::new();
    loop {
        line.clear();
        r.read_line(&mut line).map_err(|e| format!("chunk size: {e}"))?;
        let size = line.trim().split(';').next().unwrap_or("");
        let n = u64::from_str_radix(size, 16).map_err(|_| format!("chunk size `{}`", line.trim()))?;
        // The chunk, then its CRLF (after the last, empty one: the end).
        std::io::copy(&mut r.by_ref().take(n + 2), &mut std::io::sink()).map_err(|e| format!("chunk: {e}"))?;
        if n == 0 {
            return Ok(());
        }
    }
}

fn client(o: &Options, start: &Barrier) -> Tally {
    let mut t = Tally::default();
    let request = format!("GET {} HTTP/1.1\r\nHost: {}\r\n\r\n", o.target, o.authority);
    start.wait();
    let deadline = Instant::now() + Duration::from_secs_f64(o.seconds);
    let mut conn: Option<BufReader<TcpStream>> = None;
    let mut done = 0;
    while Instant::now() < deadline && o.requests.is_none_or(|n| done < n) {
        done += 1;
        let began = Instant::now();
        let mut r = match conn.take() {
            Some(r) => r,
            None => match TcpStream::connect(&o.authority) {
                Ok(s) => BufReader::new(s),
                Err(e) => {
                    t.error(format!("connect: {}", e.kind()));
                    std::thread::sleep(Duration::from_millis(10));
                    continue;
                }
            },
        };
        if let Err(e) = r.get_mut().write_all(request.as_bytes()) {
            t.error(format!("sending: {}", e.kind()));
            continue;
        }
        match read_answer(&mut r) {
            Ok((200, close)) => {
                t.latencies_us.push(began.elapsed().as_micros() as u64);
                if !close && !o.new_connection {
                    conn = Some(r);
                }
            }
            Ok((status, _)) => t.error(format!("status {status}")),
            Err(e) => t.error(e),
        }
    }
    t
}

fn percentile_ms(sorted_us: &[u64], p: f64) -> f64 {
    if sorted_us.is_empty() {
        return f64::NAN;
    }
    let k = ((sorted_us.len() - 1) as f64 * p).round() as usize;
    sorted_us[k] as f64 / 1000.0
}

fn main() -> ExitCode {
    let o = match parse_args() {
        Ok(o) => Arc::new(o),
        Err(e) => {
            eprintln!(
                "error: {e}\nusage: load [--clients N] [--seconds S] [--requests N] [--idle N] [--new-connection] URL"
            );
            return ExitCode::from(2);
        }
    };
    let idle: Vec<TcpStream> = (0..o.idle)
        .filter_map(|_| TcpStream::connect(&o.authority).ok())
        .collect();
    if o.idle > 0 {
        println!("idle connections opened: {} of {}", idle.len(), o.idle);
    }
    let start = Arc::new(Barrier::new(o.clients + 1));
    let clients: Vec<_> = (0..o.clients)
        .map(|_| {
            let (o, start) = (Arc::clone(&o), Arc::clone(&start));
            std::thread::spawn(move || client(&o, &start))
        })
        .collect();
    start.wait();
    let began = Instant::now();
    let mut all = Tally::default();
    for c in clients {
        match c.join() {
            Ok(t) => {
                all.latencies_us.extend(t.latencies_us);
                for (e, n) in t.errors {
                    *all.errors.entry(e).or_default() += n;
                }
            }
            Err(_) => all.error("a client thread failed".into()),
        }
    }
    let elapsed_s = began.elapsed().as_secs_f64();
    if o.idle > 0 {
        let open = idle.iter().filter(|s| still_open(s)).count();
        println!("idle connections still open at the end: {open}");
    }
    all.latencies_us.sort_unstable();
    let n = all.latencies_us.len();
    let errors: usize = all.errors.values().sum();
    let kinds: Vec<String> = all.errors.iter().map(|(e, n)| format!("{e}: {n}")).collect();
    println!(
        "{} clients, {elapsed_s:.1} s: {n} answers, {:.1} requests/s, p50 {:.1} ms, p99 {:.1} ms, errors {errors}{}",
        o.clients,
        n as f64 / elapsed_s,
        percentile_ms(&all.latencies_us, 0.50),
        percentile_ms(&all.latencies_us, 0.99),
        if kinds.is_empty() {
            String::new()
        } else {
            format!(" ({})", kinds.join(", "))
        }
    );
    if errors > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// Has the server left this connection open (no end of stream, no error)?
fn still_open(s: &TcpStream) -> bool {
    let mut buf = [0u8; 1];
    if s.set_nonblocking(true).is_err() {
        return false;
    }
    match s.peek(&mut buf) {
        Err(e) => e.kind() == std::io::ErrorKind::WouldBlock,
        Ok(_) => false,
    }
}
