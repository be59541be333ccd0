//! The local web page of stitchkin (`stitchkin serve`): a slider per
//! adjustable parameter of a model, inputs for the material thickness and
//! the stitch length, and a live redraw of P(φ) and P′(φ), the mismatch
//! summary and the mechanism with its threads at a chosen φ (or animated
//! over the cycle).
//!
//! A thin shell over the `stitchkin` library: [`api`] checks each request
//! and answers it with the library's charts, drawings and summaries,
//! [`server`] carries those answers over HTTP (hyper's HTTP/1.1 on one
//! thread, a few worker threads computing, loopback by default, with
//! timeouts and a cap on connections: [`ServerConfig`]). The page itself is
//! one HTML file with its script inline (`src/page.html`). See docs/web.md.
//!
//! ```no_run
//! use stitchkin::model::Model;
//! use stitchkin_web::{App, Server};
//!
//! let model = Model::preset("mf7923d")?;
//! let app = App::new(model.clone(), model.defaults());
//! let server = Server::start(app, "127.0.0.1:0", 2)?;
//! println!("open {}", server.url());
//! server.join()?;
//! # Ok::<(), stitchkin::error::Error>(())
//! ```

pub mod api;
pub mod server;
pub mod view;

pub use api::{App, Reply};
pub use server::{Server, ServerConfig};
