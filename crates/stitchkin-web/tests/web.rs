//! The web page's tests in one binary (one link on two cores): the API
//! answered directly and over HTTP, the server's limits, and the page in headless Chromium.

#[path = "web/api.rs"]
mod api;
#[path = "web/browser.rs"]
mod browser;
#[path = "web/http.rs"]
mod http;
#[path = "web/limits.rs"]
mod limits;
