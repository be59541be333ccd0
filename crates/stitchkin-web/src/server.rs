//! The HTTP shell: one thread carries the connections (hyper's HTTP/1.1 on
//! a tokio current-thread runtime), a few worker threads compute the
//! answers with [`App::handle`].
//!
//! Bound to a loopback address (the default, 127.0.0.1), the server also
//! refuses requests whose `Host` is not this machine, so a web page
//! elsewhere cannot reach it through a DNS name that resolves here.
//!
//! Limits keep it answering under load ([`ServerConfig`] has the figures):
//! a connection that sends no whole request head in time, or takes nothing
//! of an answer for a while, is closed; at the cap of open connections a
//! new one takes the place of the oldest that has sent nothing since its
//! last answer (an idle keep-alive one, or one that has asked nothing for
//! a second since it opened), and gets a 503 at once when there is none; a head that is too long gets a 431 (and an
//! address too long a 414 from [`App::handle`]). When the process runs out
//! of file descriptors the listener waits and retries, serving fewer
//! connections at once from then on; only a listening socket that no longer
//! works stops the server, with an error from [`Server::join`].

use std::convert::Infallible;
use std::future::{Future, poll_fn};
use std::io;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::task::{Context, Poll};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use http_body_util::{BodyExt, Full, LengthLimitError, Limited};
use hyper::body::{Bytes, Incoming};
use hyper::header::{self, HeaderValue};
use hyper::server::conn::http1;
use hyper::service::service_fn;
use hyper::{Method, Request, Response, StatusCode};
use hyper_util::rt::{TokioIo, TokioTimer};
use stitchkin::error::{Error, IoError};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::oneshot;

use crate::api::{App, Reply, body_name, clip, max_body_bytes, too_large};

/// How the server treats its connections. Every figure has a default
/// ([`ServerConfig::default`]) fit for one user's browser and a few
/// scripts; tests use small ones.
#[derive(Debug, Clone, PartialEq)]
pub struct ServerConfig {
    /// Requests computed at the same time, at least 1 (default 2). Further
    /// requests wait their turn.
    pub threads: usize,
    /// Connections open at once, at least 1 (default 128). A connection
    /// beyond them closes the oldest open one that is idle (it has sent
    /// nothing since its last answer, or for a second since it opened) and
    /// takes its place; when none is, it is answered 503 and closed. When the process runs out
    /// of file descriptors first (`ulimit -n`), the server lowers this to
    /// what it can hold and says so on stderr.
    pub max_connections: usize,
    /// Time a connection has to send a whole request head, from its
    /// opening or from the previous answer, ms (default 10,000). A
    /// connection that sends nothing (an idle keep-alive one too) is closed
    /// after it.
    pub header_timeout_ms: u64,
    /// Time an answer waits for a client that takes none of it before the
    /// connection is closed, ms (default 10,000).
    pub write_timeout_ms: u64,
    /// The longest request head (request line and headers), bytes, at
    /// least 1,024 (default 32,768); a longer one is answered 431 and the
    /// connection closed.
    pub max_head_bytes: usize,
}

impl Default for ServerConfig {
    fn default() -> ServerConfig {
        ServerConfig {
            threads: 2,
            max_connections: 128,
            header_timeout_ms: 10_000,
            write_timeout_ms: 10_000,
            max_head_bytes: 32 * 1024,
        }
    }
}

/// A running server.
pub struct Server {
    addr: SocketAddr,
    /// Sending (or dropping) it stops the server.
    stop: oneshot::Sender<()>,
    thread: JoinHandle<Result<(), Error>>,
}

impl Server {
    /// Listens on `addr` (`127.0.0.1:0` picks a free port) and computes
    /// answers on `threads` workers (at least one); the other limits are
    /// [`ServerConfig`]'s defaults.
    pub fn start(app: App, addr: &str, threads: usize) -> Result<Server, Error> {
        Server::start_with(
            app,
            addr,
            &ServerConfig {
                threads,
                ..ServerConfig::default()
            },
        )
    }

    /// Listens on `addr` with the limits of `config`.
    pub fn start_with(app: App, addr: &str, config: &ServerConfig) -> Result<Server, Error> {
        let listener = std::net::TcpListener::bind(addr).map_err(|e| listen_error(addr, &e))?;
        let local = listener.local_addr().map_err(|e| listen_error(addr, &e))?;
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_io()
            .enable_time()
            .max_blocking_threads(config.threads.max(1))
            .thread_name("stitchkin-web")
            .build()
            .and_then(|rt| {
                listener.set_nonblocking(true)?;
                let listener = {
                    let _in_runtime = rt.enter();
                    TcpListener::from_std(listener)?
                };
                Ok((rt, listener))
            });
        let (runtime, listener) = runtime.map_err(|e| failure(format!("cannot start the server on {local}: {e}")))?;
        let shared = Arc::new(Shared::new(app, config, local.ip().is_loopback()));
        let (stop, stopped) = oneshot::channel();
        let thread = std::thread::Builder::new()
            .name("stitchkin-web".into())
            .spawn(move || {
                let result = runtime.block_on(run(listener, shared, stopped));
                // Answers still being computed get a moment to finish.
                runtime.shutdown_timeout(Duration::from_secs(5));
                result
            })
            .map_err(|e| failure(format!("cannot start the server's thread: {e}")))?;
        Ok(Server {
            addr: local,
            stop,
            thread,
        })
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
    /// process is interrupted). An error says why it stopped by itself:
    /// its listening socket no longer works.
    pub fn join(self) -> Result<(), Error> {
        let Server { stop, thread, .. } = self;
        let result = thread.join();
        drop(stop);
        result.unwrap_or_else(|_| Err(failure("the server's thread failed")))
    }

    /// Stops taking requests and waits for the answers being computed.
    pub fn stop(self) {
        let Server { stop, thread, .. } = self;
        let _ = stop.send(());
        let _ = thread.join();
    }
}

/// What `bind` failing means, in words: the cause first.
fn listen_error(addr: &str, e: &io::Error) -> Error {
    let cause = match e.kind() {
        io::ErrorKind::AddrInUse => "another program is listening on this port".to_string(),
        io::ErrorKind::AddrNotAvailable => "this address is not one of this machine's".to_string(),
        io::ErrorKind::PermissionDenied => "listening on this port needs privileges this user lacks".to_string(),
        _ => e.to_string(),
    };
    Error::Io(IoError {
        action: format!("listen on {addr}"),
        path: None,
        reason: format!("{cause} ({e})"),
        source: Some(Arc::new(io::Error::new(e.kind(), e.to_string()))),
    })
}

/// The server's own failures (starting its runtime or thread, a listener
/// that stopped working) as the library's error.
fn failure(message: impl Into<String>) -> Error {
    Error::Io(IoError::refused("serve", None, message))
}

/// What the connections share.
struct Shared {
    app: App,
    loopback: bool,
    header_timeout: Duration,
    write_timeout: Duration,
    max_head_bytes: usize,
    /// Connections open now, and how many may be.
    open: AtomicUsize,
    /// The open connections, oldest first: what the cap may close.
    slots: std::sync::Mutex<std::collections::BTreeMap<u64, Arc<Slot>>>,
    next_slot: AtomicU64,
    max_connections: AtomicUsize,
    /// Refused connections still being answered 503.
    refusing: AtomicUsize,
    /// Connections refused since the last line on stderr said so, and when
    /// that was.
    refused: AtomicUsize,
    refusals_said: std::sync::Mutex<Option<Instant>>,
}

impl Shared {
    fn new(app: App, config: &ServerConfig, loopback: bool) -> Shared {
        Shared {
            app,
            loopback,
            header_timeout: Duration::from_millis(config.header_timeout_ms.max(1)),
            write_timeout: Duration::from_millis(config.write_timeout_ms.max(1)),
            max_head_bytes: config.max_head_bytes.max(1024),
            open: AtomicUsize::new(0),
            slots: std::sync::Mutex::new(std::collections::BTreeMap::new()),
            next_slot: AtomicU64::new(0),
            max_connections: AtomicUsize::new(config.max_connections.max(1)),
            refusing: AtomicUsize::new(0),
            refused: AtomicUsize::new(0),
            refusals_said: std::sync::Mutex::new(None),
        }
    }
}

/// Counts one connection (open or being refused) while it lives.
struct Counted(Arc<Shared>, fn(&Shared) -> &AtomicUsize);

impl Counted {
    fn new(shared: &Arc<Shared>, counter: fn(&Shared) -> &AtomicUsize) -> Counted {
        counter(shared).fetch_add(1, Ordering::SeqCst);
        Counted(Arc::clone(shared), counter)
    }
}

impl Drop for Counted {
    fn drop(&mut self) {
        (self.1)(&self.0).fetch_sub(1, Ordering::SeqCst);
    }
}

/// How long a new connection has to send its first request before it may
/// be closed to make room, ms: a client that has just connected is about
/// to ask.
const FIRST_REQUEST_GRACE_MS: u64 = 1000;

/// One open connection, as the cap sees it.
struct Slot {
    opened: Instant,
    /// It has asked at least once.
    asked: AtomicBool,
    /// Bytes came in since its last request was read: a request is on
    /// its way.
    received: AtomicBool,
    /// Requests being computed on it.
    computing: AtomicUsize,
    /// An answer waits for the client to take it.
    sending: AtomicBool,
    /// Chosen to make room; `close` tells its task.
    closing: AtomicBool,
    close: tokio::sync::Notify,
}

impl Slot {
    fn new() -> Slot {
        Slot {
            opened: Instant::now(),
            asked: false.into(),
            received: false.into(),
            computing: 0.into(),
            sending: false.into(),
            closing: false.into(),
            close: tokio::sync::Notify::new(),
        }
    }

    /// Neither asking, computing nor sending, and no longer new.
    fn idle(&self) -> bool {
        (self.asked.load(Ordering::SeqCst) || self.opened.elapsed() >= Duration::from_millis(FIRST_REQUEST_GRACE_MS))
            && !self.received.load(Ordering::SeqCst)
            && self.computing.load(Ordering::SeqCst) == 0
            && !self.sending.load(Ordering::SeqCst)
            && !self.closing.load(Ordering::SeqCst)
    }
}

/// Holds a slot in [`Shared::slots`] while its connection lives.
struct Registered(Arc<Shared>, u64);

impl Drop for Registered {
    fn drop(&mut self) {
        if let Ok(mut slots) = self.0.slots.lock() {
            slots.remove(&self.1);
        }
    }
}

/// Makes room for one more connection at the cap: closes the oldest open
/// connection that has sent nothing since its last answer and is neither
/// computing nor sending one. True when there is room: one was closed, or
/// enough are closing already (chosen before, their tasks not yet run);
/// false when every connection is busy. (A connection still sending its
/// request head is left to the head timeout.)
fn make_room(shared: &Shared) -> bool {
    let Ok(slots) = shared.slots.lock() else {
        return false;
    };
    let closing = slots
        .values()
        .filter(|slot| slot.closing.load(Ordering::SeqCst))
        .count();
    let staying = shared.open.load(Ordering::SeqCst).saturating_sub(closing);
    if staying < shared.max_connections.load(Ordering::SeqCst) {
        return true;
    }
    match slots.values().find(|slot| slot.idle()) {
        Some(slot) => {
            slot.closing.store(true, Ordering::SeqCst);
            slot.close.notify_one();
            true
        }
        None => false,
    }
}

/// Counts a request being computed on a connection while it lives.
struct Computing(Arc<Slot>);

impl Computing {
    fn new(slot: &Arc<Slot>) -> Computing {
        slot.computing.fetch_add(1, Ordering::SeqCst);
        slot.received.store(false, Ordering::SeqCst);
        slot.asked.store(true, Ordering::SeqCst);
        Computing(Arc::clone(slot))
    }
}

impl Drop for Computing {
    fn drop(&mut self) {
        self.0.computing.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Accepts connections until `stopped` fires (or its sender is dropped),
/// or until the listening socket fails.
async fn run(listener: TcpListener, shared: Arc<Shared>, mut stopped: oneshot::Receiver<()>) -> Result<(), Error> {
    let addr = listener.local_addr().ok();
    let mut accepting = tokio::spawn(accept_loop(listener, shared));
    let outcome = poll_fn(|cx| {
        if let Poll::Ready(r) = Pin::new(&mut accepting).poll(cx) {
            return Poll::Ready(Some(r));
        }
        if Pin::new(&mut stopped).poll(cx).is_ready() {
            return Poll::Ready(None);
        }
        Poll::Pending
    })
    .await;
    match outcome {
        None => Ok(()),
        Some(Ok(Ok(()))) => Ok(()),
        Some(Ok(Err(e))) => Err(failure(format!(
            "the server on {} stopped listening: {e}; start it again",
            addr.map_or_else(|| "?".into(), |a| a.to_string())
        ))),
        Some(Err(_)) => Err(failure("the server's listener failed")),
    }
}

/// What an error of `accept` means for the listener.
#[derive(Debug, PartialEq)]
enum AcceptError {
    /// One connection went wrong before it was taken: take the next.
    Connection,
    /// Out of file descriptors or memory: wait, then try again.
    Exhausted,
    /// The listening socket itself no longer works.
    Broken,
}

fn accept_error(e: &io::Error) -> AcceptError {
    match e.raw_os_error() {
        Some(libc::EMFILE | libc::ENFILE | libc::ENOBUFS | libc::ENOMEM) => AcceptError::Exhausted,
        Some(libc::EBADF | libc::EINVAL | libc::ENOTSOCK | libc::EFAULT) => AcceptError::Broken,
        _ => AcceptError::Connection,
    }
}

/// The longest wait between two tries of `accept` when out of file
/// descriptors, ms.
const MAX_BACKOFF_MS: u64 = 1000;

/// File descriptors kept free below the limit the process ran into, to
/// answer a refused connection 503 rather than leave it waiting (more than
/// [`MAX_LINGERING`]).
const SPARE_DESCRIPTORS: usize = 32;

async fn accept_loop(listener: TcpListener, shared: Arc<Shared>) -> io::Result<()> {
    let mut backoff_ms = 0;
    loop {
        match listener.accept().await {
            Ok((stream, _)) => {
                backoff_ms = 0;
                admit(stream, &shared);
            }
            Err(e) => match accept_error(&e) {
                AcceptError::Connection => {}
                AcceptError::Broken => return Err(e),
                AcceptError::Exhausted => {
                    let descriptors = matches!(e.raw_os_error(), Some(libc::EMFILE | libc::ENFILE));
                    if backoff_ms == 0 && descriptors {
                        lower_cap(&shared, &e);
                    }
                    backoff_ms = (backoff_ms * 2).clamp(10, MAX_BACKOFF_MS);
                    tokio::time::sleep(Duration::from_millis(backoff_ms)).await;
                }
            },
        }
    }
}

/// Out of file descriptors with `open` connections: serve fewer from now
/// on, so that later ones are refused with a 503 instead of waiting.
fn lower_cap(shared: &Shared, e: &io::Error) {
    let in_use = shared.open.load(Ordering::SeqCst) + shared.refusing.load(Ordering::SeqCst);
    let cap = in_use.saturating_sub(SPARE_DESCRIPTORS).max(1);
    let before = shared.max_connections.fetch_min(cap, Ordering::SeqCst);
    if cap < before {
        eprintln!(
            "stitchkin serve: out of file descriptors ({e}) with {in_use} connections open; serving at most \
             {cap} at once from now (raise the limit of open files, `ulimit -n`, to serve more)"
        );
    }
}

/// Serves `stream`, or refuses it with a 503 when the connections are full.
fn admit(stream: TcpStream, shared: &Arc<Shared>) {
    // Answers go out as soon as they are written (no wait for the ACK of
    // the previous segment).
    let _ = stream.set_nodelay(true);
    // At the cap, an idle connection makes room: a client that holds
    // connections open without asking keeps nobody else out for long.
    if shared.open.load(Ordering::SeqCst) >= shared.max_connections.load(Ordering::SeqCst) && !make_room(shared) {
        refuse(stream, shared);
        return;
    }
    let count = Counted::new(shared, |s| &s.open);
    let slot = Arc::new(Slot::new());
    let id = shared.next_slot.fetch_add(1, Ordering::SeqCst);
    if let Ok(mut slots) = shared.slots.lock() {
        slots.insert(id, Arc::clone(&slot));
    }
    let registered = Registered(Arc::clone(shared), id);
    let watched = Watched {
        stream,
        slot: Arc::clone(&slot),
    };
    let io = WriteTimeout::new(TokioIo::new(watched), shared.write_timeout, Arc::clone(&slot));
    let service = {
        let (shared, slot) = (Arc::clone(shared), Arc::clone(&slot));
        service_fn(move |request| {
            let computing = Computing::new(&slot);
            let answered = answer(request, Arc::clone(&shared));
            async move {
                let reply = answered.await;
                drop(computing);
                reply
            }
        })
    };
    let connection = http1::Builder::new()
        .timer(TokioTimer::new())
        .header_read_timeout(shared.header_timeout)
        .max_header_size(shared.max_head_bytes)
        // `Content-Type`, as the answers spelled it before, not `content-type`.
        .title_case_headers(true)
        .serve_connection(io, service);
    tokio::spawn(async move {
        // A client that goes away or times out is not the server's problem;
        // a connection chosen to make room is dropped, which closes it.
        let mut connection = std::pin::pin!(connection);
        let mut closed = std::pin::pin!(slot.close.notified());
        poll_fn(|cx| {
            if connection.as_mut().poll(cx).is_ready() || closed.as_mut().poll(cx).is_ready() {
                Poll::Ready(())
            } else {
                Poll::Pending
            }
        })
        .await;
        drop(registered);
        drop(count);
    });
}

/// How long a refused connection is kept to read the request it sent
/// (closing with unread data would reset the connection, and the client
/// could lose the 503), ms.
const REFUSE_LINGER_MS: u64 = 1000;

/// Refused connections kept open at once to read their request.
const MAX_LINGERING: usize = 16;

/// Answers 503 on a connection beyond the cap and closes it.
fn refuse(stream: TcpStream, shared: &Arc<Shared>) {
    let cap = shared.max_connections.load(Ordering::SeqCst);
    say_refusals(shared, cap);
    let body = Reply::error(
        503,
        format!("the server has {cap} connections open, as many as it serves at once"),
        Some("try again in a moment; close pages or scripts that hold connections open"),
    )
    .body;
    let head = format!(
        "HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json; charset=utf-8\r\n\
         Content-Length: {}\r\nRetry-After: 1\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n",
        body.len()
    );
    // What the client sent already (its request, usually) is read, so that
    // closing at once does not reset the connection.
    let mut scratch = [0u8; 4096];
    for _ in 0..16 {
        if !matches!(stream.try_read(&mut scratch), Ok(n) if n > 0) {
            break;
        }
    }
    // A fresh connection's send buffer takes these few hundred bytes whole.
    let _ = stream.try_write(&[head.as_bytes(), &body].concat());
    // A few are kept open a moment to read a request still on its way;
    // under a flood the others are closed at once.
    if shared.refusing.load(Ordering::SeqCst) >= MAX_LINGERING {
        return;
    }
    let count = Counted::new(shared, |s| &s.refusing);
    tokio::spawn(async move {
        let drain = async {
            let mut buf = [0u8; 4096];
            let mut read = 0;
            while read < 64 * 1024 && stream.readable().await.is_ok() {
                match stream.try_read(&mut buf) {
                    Ok(0) => break,
                    Ok(n) => read += n,
                    Err(e) if e.kind() == io::ErrorKind::WouldBlock => {}
                    Err(_) => break,
                }
            }
        };
        let _ = tokio::time::timeout(Duration::from_millis(REFUSE_LINGER_MS), drain).await;
        drop(count);
    });
}

/// How often stderr says that connections are being refused, s.
const REFUSALS_SAID_EVERY_S: u64 = 10;

/// Counts a refused connection; says so on stderr at the first and then at
/// most every [`REFUSALS_SAID_EVERY_S`].
fn say_refusals(shared: &Shared, cap: usize) {
    let refused = shared.refused.fetch_add(1, Ordering::SeqCst) + 1;
    let Ok(mut said) = shared.refusals_said.lock() else {
        return;
    };
    let now = Instant::now();
    if said.is_some_and(|t| now.duration_since(t) < Duration::from_secs(REFUSALS_SAID_EVERY_S)) {
        return;
    }
    *said = Some(now);
    shared.refused.fetch_sub(refused, Ordering::SeqCst);
    eprintln!("stitchkin serve: {cap} connections open, as many as it serves; {refused} more refused with 503");
}

/// The longest piece of a request a log line shows, characters.
const LOG_CHARS: usize = 200;

async fn answer(request: Request<Incoming>, shared: Arc<Shared>) -> Result<Response<Full<Bytes>>, Infallible> {
    let method = request.method().as_str().to_string();
    let url = request.uri().path_and_query().map_or("/", |p| p.as_str()).to_string();
    let path = request.uri().path().to_string();
    let reply = match foreign_host(&request, shared.loopback) {
        Some(host) => Reply::error(
            403,
            format!(
                "this server answers requests for this machine only, not for Host `{}`",
                clip(&host, 100)
            ),
            Some("open the page at http://127.0.0.1:PORT/ (or http://localhost:PORT/)"),
        ),
        None if request.method() == Method::POST && foreign_origin(&request) => Reply::error(
            403,
            "a model file or a measured curve is loaded from this server's own page only",
            Some("choose the file with the page's file picker"),
        ),
        None => {
            let content_type = request
                .headers()
                .get(header::CONTENT_TYPE)
                .and_then(|v| v.to_str().ok())
                .map(str::to_string);
            let body = if request.method() == Method::POST {
                read_body(request, &path, shared.header_timeout).await
            } else {
                Ok(Bytes::new())
            };
            match body {
                Err(reply) => reply,
                Ok(body) => {
                    let (app, method, url) = (Arc::clone(&shared), method.clone(), url.clone());
                    tokio::task::spawn_blocking(move || {
                        app.app.handle_body(&method, &url, content_type.as_deref(), &body)
                    })
                    .await
                    .unwrap_or_else(|_| Reply::error(500, "the answer could not be computed", None))
                }
            }
        }
    };
    if reply.status >= 400 {
        eprintln!(
            "{method} {} → {} {}",
            clip(&url, LOG_CHARS),
            reply.status,
            clip(reply.text(), LOG_CHARS)
        );
    }
    let allow = match path.as_str() {
        "/api/models" => "GET, HEAD, POST",
        "/api/measured" => "POST",
        _ => "GET, HEAD",
    };
    Ok(response(reply, allow))
}

/// The body of a POST to `path`, at most [`max_body_bytes`] and within
/// `timeout`; otherwise the answer that says so (413, 408).
async fn read_body(request: Request<Incoming>, path: &str, timeout: Duration) -> Result<Bytes, Reply> {
    let limit = max_body_bytes(path);
    let declared = request
        .headers()
        .get(header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().parse::<u64>().ok());
    if let Some(n) = declared
        && n > limit as u64
    {
        return Err(too_large(path, usize::try_from(n).ok()));
    }
    let what = body_name(path);
    let body = Limited::new(request.into_body(), limit);
    match tokio::time::timeout(timeout, body.collect()).await {
        Err(_) => Err(Reply::error(
            408,
            format!("{what} did not arrive within {} s", timeout.as_secs()),
            Some("send it again"),
        )),
        Ok(Err(e)) if e.downcast_ref::<LengthLimitError>().is_some() => Err(too_large(path, None)),
        Ok(Err(e)) => Err(Reply::error(
            400,
            format!("{what} could not be read: {}", clip(&e.to_string(), 100)),
            Some("send it again"),
        )),
        Ok(Ok(collected)) => Ok(collected.to_bytes()),
    }
}

/// Whether a request carries an `Origin` that is not the host it asks (a
/// page elsewhere sending to this server).
fn foreign_origin(request: &Request<Incoming>) -> bool {
    let Some(origin) = request.headers().get(header::ORIGIN) else {
        return false;
    };
    let origin = String::from_utf8_lossy(origin.as_bytes());
    let authority = origin.split_once("://").map_or("", |(_, a)| a).trim_end_matches('/');
    let host = request
        .headers()
        .get(header::HOST)
        .map(|h| String::from_utf8_lossy(h.as_bytes()).into_owned())
        .or_else(|| request.uri().authority().map(|a| a.as_str().to_string()));
    host.is_none_or(|h| !h.eq_ignore_ascii_case(authority))
}

/// The host a request names (its `Host`, or the authority of an absolute
/// address) when the server is on loopback and that host is not this
/// machine.
fn foreign_host(request: &Request<Incoming>, loopback: bool) -> Option<String> {
    if !loopback {
        return None;
    }
    let authority = request.uri().authority().map(|a| a.as_str().to_string());
    let host = request
        .headers()
        .get(header::HOST)
        .map(|h| String::from_utf8_lossy(h.as_bytes()).into_owned());
    [authority, host].into_iter().flatten().find(|h| !is_local_host(h))
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

fn response(reply: Reply, allow: &'static str) -> Response<Full<Bytes>> {
    let status = StatusCode::from_u16(reply.status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR);
    let allow = (status == StatusCode::METHOD_NOT_ALLOWED).then_some(allow);
    let mut response = Response::new(Full::new(Bytes::from(reply.body)));
    *response.status_mut() = status;
    let headers = response.headers_mut();
    for (name, value) in [
        (header::CONTENT_TYPE, Some(reply.content_type)),
        (header::CACHE_CONTROL, Some("no-store")),
        (header::X_CONTENT_TYPE_OPTIONS, Some("nosniff")),
        (
            header::CONTENT_SECURITY_POLICY,
            Some(
                "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data:; \
                 connect-src 'self'",
            ),
        ),
        (header::ALLOW, allow),
    ] {
        if let Some(value) = value.and_then(|v| HeaderValue::from_str(v).ok()) {
            headers.insert(name, value);
        }
    }
    response
}

/// A connection's socket that marks its slot when bytes come in.
struct Watched {
    stream: TcpStream,
    slot: Arc<Slot>,
}

impl tokio::io::AsyncRead for Watched {
    fn poll_read(self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &mut tokio::io::ReadBuf<'_>) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        let before = buf.filled().len();
        let poll = Pin::new(&mut this.stream).poll_read(cx, buf);
        if buf.filled().len() > before {
            this.slot.received.store(true, Ordering::SeqCst);
        }
        poll
    }
}

impl tokio::io::AsyncWrite for Watched {
    fn poll_write(self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &[u8]) -> Poll<io::Result<usize>> {
        Pin::new(&mut self.get_mut().stream).poll_write(cx, buf)
    }

    fn poll_write_vectored(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        Pin::new(&mut self.get_mut().stream).poll_write_vectored(cx, bufs)
    }

    fn is_write_vectored(&self) -> bool {
        self.stream.is_write_vectored()
    }

    fn poll_flush(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().stream).poll_flush(cx)
    }

    fn poll_shutdown(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().stream).poll_shutdown(cx)
    }
}

/// A connection whose writes fail (and so close it) when the client takes
/// nothing of an answer for `timeout`.
struct WriteTimeout {
    io: TokioIo<Watched>,
    timeout: Duration,
    /// Running while a write waits for the client.
    stalled: Option<Pin<Box<tokio::time::Sleep>>>,
    /// Its connection's slot: `sending` while a write waits.
    slot: Arc<Slot>,
}

impl WriteTimeout {
    fn new(io: TokioIo<Watched>, timeout: Duration, slot: Arc<Slot>) -> WriteTimeout {
        WriteTimeout {
            io,
            timeout,
            stalled: None,
            slot,
        }
    }

    /// `poll`, a write's progress: none for `timeout` is an error.
    fn watch<T>(&mut self, cx: &mut Context<'_>, poll: Poll<io::Result<T>>) -> Poll<io::Result<T>> {
        self.slot.sending.store(poll.is_pending(), Ordering::SeqCst);
        if poll.is_ready() {
            self.stalled = None;
            return poll;
        }
        let timeout = self.timeout;
        let stalled = self
            .stalled
            .get_or_insert_with(|| Box::pin(tokio::time::sleep(timeout)));
        if stalled.as_mut().poll(cx).is_ready() {
            self.stalled = None;
            return Poll::Ready(Err(io::Error::new(
                io::ErrorKind::TimedOut,
                "the client took nothing of the answer in time",
            )));
        }
        Poll::Pending
    }
}

impl hyper::rt::Read for WriteTimeout {
    fn poll_read(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: hyper::rt::ReadBufCursor<'_>,
    ) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().io).poll_read(cx, buf)
    }
}

impl hyper::rt::Write for WriteTimeout {
    fn poll_write(self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &[u8]) -> Poll<io::Result<usize>> {
        let this = self.get_mut();
        let poll = Pin::new(&mut this.io).poll_write(cx, buf);
        this.watch(cx, poll)
    }

    fn poll_write_vectored(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        let this = self.get_mut();
        let poll = Pin::new(&mut this.io).poll_write_vectored(cx, bufs);
        this.watch(cx, poll)
    }

    fn is_write_vectored(&self) -> bool {
        self.io.is_write_vectored()
    }

    fn poll_flush(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        let poll = Pin::new(&mut this.io).poll_flush(cx);
        this.watch(cx, poll)
    }

    fn poll_shutdown(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        let poll = Pin::new(&mut this.io).poll_shutdown(cx);
        this.watch(cx, poll)
    }
}

#[cfg(test)]
mod tests {
    use super::{AcceptError, accept_error, is_local_host};

    #[test]
    fn local_hosts() {
        for h in ["127.0.0.1:8080", "localhost:1", "LOCALHOST", "[::1]:80", "127.0.0.1"] {
            assert!(is_local_host(h), "{h}");
        }
        for h in ["evil.example:8080", "127.0.0.1.example", "10.0.0.1:80", "[::2]:80", ""] {
            assert!(!is_local_host(h), "{h}");
        }
    }

    #[test]
    fn accept_errors() {
        let os = std::io::Error::from_raw_os_error;
        assert_eq!(accept_error(&os(libc::EMFILE)), AcceptError::Exhausted);
        assert_eq!(accept_error(&os(libc::ENFILE)), AcceptError::Exhausted);
        assert_eq!(accept_error(&os(libc::ECONNABORTED)), AcceptError::Connection);
        assert_eq!(accept_error(&os(libc::EPROTO)), AcceptError::Connection);
        assert_eq!(accept_error(&os(libc::EBADF)), AcceptError::Broken);
    }
}
