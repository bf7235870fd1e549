//! SMD-R1-036 on a real link: `smd-ethercat` watches its interface's carrier; when the master's end
//! goes down the units in Op drop to Safe-Op with the error indication, and they stay there after the
//! link is back until the master requests Op again.

mod common;
use testkit::link;

use std::process::Command;
use std::time::Duration;

use ethercat_slave::esc::al::state;
use ethercat_slave::master::{self, SocketWire};
use ethercat_slave::raw::RawSocket;

fn set_link(iface: &str, up: bool) {
    let s = Command::new("ip")
        .args(["link", "set", iface, if up { "up" } else { "down" }])
        .status()
        .expect("ip");
    assert!(s.success());
}

/// SMD-R1-036: a cable disconnect (the master's end down for 300 ms) moves the units to Safe-Op;
/// after reconnecting, AL status reads Safe-Op + error (0x0014, code 0x001B) until Op is requested.
#[test]
fn smd_r1_036_lost_carrier_drops_op_to_safe_op() {
    let link = link::Link::up(&["--units", "2"]);
    let socket = RawSocket::open(&link.master).expect("raw socket");
    let mut w = SocketWire::new(socket, 2);
    master::bring_up(&mut w, state::OP).unwrap();
    // Only the link is under test here: the SyncManager watchdog is switched off (0x0420 = 0).
    for k in 0..2 {
        master::fpwr(&mut w, k, 0x0420, vec![0, 0]).unwrap();
    }
    std::thread::sleep(Duration::from_millis(300));
    for k in 0..2 {
        assert_eq!(
            master::al(&mut w, k).unwrap(),
            (0x0008, 0),
            "unit {k} in Op"
        );
    }
    set_link(&link.master, false);
    std::thread::sleep(Duration::from_millis(300));
    set_link(&link.master, true);
    // The carrier of the pair takes a moment to come back.
    let mut back = None;
    for _ in 0..100 {
        if let Ok(s) = master::al(&mut w, 0) {
            back = Some(s);
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(
        back,
        Some((0x0014, 0x001B)),
        "unit 0 after the link is back"
    );
    assert_eq!(master::al(&mut w, 1).unwrap(), (0x0014, 0x001B));
    std::thread::sleep(Duration::from_millis(200));
    assert_eq!(
        master::al(&mut w, 0).unwrap().0,
        0x0014,
        "not back to Op by itself"
    );
    master::request(&mut w, state::OP | 0x10).unwrap();
    for k in 0..2 {
        assert_eq!(
            master::al(&mut w, k).unwrap(),
            (0x0008, 0),
            "unit {k} in Op again"
        );
    }
}
