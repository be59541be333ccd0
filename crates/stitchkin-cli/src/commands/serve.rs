//! `stitchkin serve`: the live web page (stitchkin_web), starting with one
//! model; the page shows any preset or a model file of the user's as well.

use std::io::Write;
use std::net::IpAddr;

use stitchkin::error::{Error, ParamError};
use stitchkin_web::{App, Server, ServerConfig};

use crate::common::{ModelArgs, load, note_line};

/// A local web page: a slider per adjustable parameter, thickness and
/// stitch length inputs, and live P/P′, mismatch and mechanism drawing;
/// any preset, or a model file loaded on the page, besides the model given.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  stitchkin serve\n  stitchkin serve --preset altin504 --port 8081\n  \
    stitchkin serve my-machine.toml --set r1=5 --port 0\n  \
    stitchkin serve --max-connections 16 --timeout-s 5\n\n\
    Open the address it prints in a browser; Ctrl-C stops it. The page starts with the model given\n\
    and can show any preset or load a model file; its address keeps the model and the settings.\n\
    It listens on 127.0.0.1 only, unless --bind says otherwise, and answers requests for this\n\
    machine's host names only (docs/web.md)."
)]
pub(crate) struct Args {
    #[command(flatten)]
    model: ModelArgs,
    /// TCP port to listen on (0: any free port, printed at start).
    #[arg(long, default_value_t = 8080, value_name = "PORT")]
    port: u16,
    /// Address to listen on. The default, 127.0.0.1, keeps the page on this
    /// machine; another address exposes it to the network.
    #[arg(long, default_value = "127.0.0.1", value_name = "IP")]
    bind: IpAddr,
    /// Requests computed at the same time.
    #[arg(long, default_value_t = 2, value_name = "N")]
    threads: usize,
    /// Connections open at once; at the cap a new one closes the oldest
    /// idle one, or gets a 503 when none is idle.
    #[arg(long, default_value_t = ServerConfig::default().max_connections, value_name = "N")]
    max_connections: usize,
    /// Seconds a client has to send a whole request head (an idle
    /// keep-alive connection too), and to take some of an answer, before
    /// its connection is closed.
    #[arg(long, default_value_t = ServerConfig::default().header_timeout_ms / 1000, value_name = "S")]
    timeout_s: u64,
}

/// The most connections `--max-connections` may ask for.
const MAX_CONNECTIONS: usize = 65_536;

/// The longest `--timeout-s`, s.
const MAX_TIMEOUT_S: u64 = 3600;

pub(crate) fn run(args: Args) -> Result<(), Error> {
    if !(1..=64).contains(&args.threads) {
        return Err(Error::Param(ParamError::general(
            format!("--threads {} is outside 1…64", args.threads),
            Some("one thread per core is plenty (the default is 2)".into()),
        )));
    }
    if !(1..=MAX_CONNECTIONS).contains(&args.max_connections) {
        return Err(Error::Param(ParamError::general(
            format!("--max-connections {} is outside 1…{MAX_CONNECTIONS}", args.max_connections),
            Some("a browser holds about 6 connections; the default is 128 (the open-file limit, `ulimit -n`, bounds it too)".into()),
        )));
    }
    if !(1..=MAX_TIMEOUT_S).contains(&args.timeout_s) {
        return Err(Error::Param(ParamError::general(
            format!("--timeout-s {} is outside 1…{MAX_TIMEOUT_S}", args.timeout_s),
            Some("the default, 10 s, lets a slow client send its request".into()),
        )));
    }
    let (model, params) = load(&args.model)?;
    let addr = std::net::SocketAddr::new(args.bind, args.port);
    let config = ServerConfig {
        threads: args.threads,
        max_connections: args.max_connections,
        header_timeout_ms: args.timeout_s * 1000,
        write_timeout_ms: args.timeout_s * 1000,
        ..ServerConfig::default()
    };
    let server =
        Server::start_with(App::new(model, params), &addr.to_string(), &config).map_err(|e| listen_error(e, &args))?;
    if !args.bind.is_loopback() {
        note_line(&format!(
            "warning: listening on {} — anyone who can reach this machine can use the page",
            args.bind
        ));
    }
    // The address on stdout (a script can read it), flushed at once.
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "stitchkin serve: open {}  (Ctrl-C stops)", server.url());
    let _ = out.flush();
    drop(out);
    server.join()
}

/// The server could not listen (the message says why): the fix, for a
/// --bind that is not this machine's or for a --port that cannot be had.
fn listen_error(e: Error, args: &Args) -> Error {
    let Error::Io(io) = e else { return e };
    let help = match io.kind() {
        Some(std::io::ErrorKind::AddrNotAvailable) => format!(
            "{} is not an address of this machine: leave --bind out (127.0.0.1: this machine only), or give one of \
             its addresses (0.0.0.0: all of them)",
            args.bind
        ),
        Some(std::io::ErrorKind::AddrInUse | std::io::ErrorKind::PermissionDenied) => {
            "choose another port with --port (above 1023, which need no privileges), or --port 0 for any free one"
                .to_string()
        }
        _ => return Error::Io(io),
    };
    Error::Param(ParamError::general(io.to_string(), Some(help)))
}
