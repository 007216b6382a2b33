//! One process-wide Ctrl-C / SIGTERM handler (`proleg::signal`): every live subscriber's
//! flag is raised by one real signal, a dropped one's is not. The only test in its process,
//! so the signal reaches no other test.

use std::sync::mpsc::channel;
use std::time::Duration;

#[test]
fn one_signal_raises_every_live_subscriber_and_no_dropped_one() {
    let (tx, rx) = channel();
    let run = proleg::signal::subscribe().unwrap();
    let window = proleg::signal::subscribe_with(move || tx.send(()).unwrap()).unwrap();
    let dropped = proleg::signal::subscribe().unwrap();
    let dropped_flag = dropped.flag();
    drop(dropped);
    assert!(!run.is_raised() && !window.is_raised());
    let sent = std::process::Command::new("kill")
        .args(["-TERM", &std::process::id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    // The wake-up comes after the flags are raised, on the handler's thread.
    rx.recv_timeout(Duration::from_secs(30))
        .expect("the handler woke the window's subscriber");
    assert!(run.is_raised(), "the first subscriber's flag");
    assert!(window.is_raised(), "the second subscriber's flag");
    assert!(
        !dropped_flag.is_set(),
        "a dropped subscription hears nothing"
    );
    assert_eq!(
        proleg::signal::received(),
        Some(15),
        "the signal is remembered"
    );
    // A later subscriber starts lowered.
    assert!(!proleg::signal::subscribe().unwrap().is_raised());
}
