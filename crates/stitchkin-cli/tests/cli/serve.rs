//! `stitchkin serve` from the command line: it starts and answers (the
//! README test), and refuses what it cannot do before listening.

use super::fails;

#[test]
fn serve_refuses_a_port_in_use_with_the_fix() {
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    let err = fails(&["serve", "--port", &port]);
    assert!(err.contains("cannot listen") && err.contains("--port 0"), "{err}");
}

#[test]
fn serve_refuses_an_address_not_of_this_machine_with_the_fix() {
    // 192.0.2.1 is kept for documentation: no machine has it (unless this
    // one lets a program listen on any address, then there is nothing to
    // check).
    if std::net::TcpListener::bind("192.0.2.1:0").is_ok() {
        return;
    }
    let err = fails(&["serve", "--bind", "192.0.2.1", "--port", "0"]);
    assert!(
        err.contains("not one of this machine's") && err.contains("leave --bind out"),
        "{err}"
    );
    assert!(!err.contains("another program"), "{err}");
}

#[test]
fn serve_refuses_bad_options_and_models_before_listening() {
    assert!(fails(&["serve", "--threads", "0"]).contains("--threads 0 is outside 1…64"));
    assert!(fails(&["serve", "--max-connections", "0"]).contains("--max-connections 0 is outside 1…65536"));
    assert!(fails(&["serve", "--timeout-s", "0"]).contains("--timeout-s 0 is outside 1…3600"));
    assert!(fails(&["serve", "--timeout-s", "3601"]).contains("outside"));
    assert!(fails(&["serve", "no-such-model.toml"]).contains("no-such-model.toml"));
    assert!(fails(&["serve", "--set", "r1=99"]).contains("outside its adjustable range"));
    assert!(fails(&["serve", "--bind", "not-an-ip"]).contains("not-an-ip"));
}
