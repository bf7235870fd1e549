//! `--capture FILE` of the emulators on a veth pair (see `testkit::link`): a broadcast read of AL
//! status from this end, and the capture `smd-ethercat` leaves when stopped with Ctrl-C: the frame
//! as it arrived (inbound), then the answer as it left (outbound), byte for byte. Needs root.

use std::time::{Duration, Instant, SystemTime};

use ecat_link::raw::RawSocket;
use link_capture::pcapng::{Direction, Reader, LINKTYPE_ETHERNET};
use testkit::link::Link;

/// A BRD of AL status (0x0130, 2 bytes) with index 0x42 from source 10:10:10:10:10:10, padded to
/// 60 bytes (ETG.1000.4 §5: the EtherCAT header 0x100E = type 1, 14 bytes of datagram).
#[rustfmt::skip]
const BRD: [u8; 60] = {
    let mut f = [0u8; 60];
    let head: [u8; 30] = [
        0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x88, 0xA4,
        0x0E, 0x10,
        0x07, 0x42, 0x00, 0x00, 0x30, 0x01, 0x02, 0x00, 0x00, 0x00,
        0x00, 0x00,
        0x00, 0x00,
    ];
    let mut k = 0;
    while k < 30 {
        f[k] = head[k];
        k += 1;
    }
    f
};

#[test]
fn smd_ethercat_captures_what_it_receives_and_answers() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("smd.pcapng");
    let start = SystemTime::now();
    let mut link = Link::up(&["--units", "2", "--capture", file.to_str().unwrap()]);
    let socket = RawSocket::open(&link.master).unwrap();
    socket.send(&BRD).unwrap();
    let mut buf = [0u8; 1514];
    let deadline = Instant::now() + Duration::from_secs(5);
    let answer = loop {
        assert!(Instant::now() < deadline, "no answer within 5 s");
        socket.wait(Duration::from_millis(100)).unwrap();
        if let Some(n) = socket.recv(&mut buf).unwrap() {
            if buf[6] & 0x02 != 0 {
                break buf[..n].to_vec();
            }
        }
    };
    // Both units in Init (AL status 0x0001, OR'd), working counter 2, the address incremented by
    // each unit (a broadcast's ADP, ETG.1000.4 §5.4.1.2); the source's locally administered bit
    // set.
    let mut expected = BRD;
    expected[6] = 0x12;
    expected[18] = 0x02;
    expected[26] = 0x01;
    expected[28] = 0x02;
    assert_eq!(answer, expected);
    link.stop();
    let bytes = std::fs::read(&file).unwrap();
    let mut r = Reader::new(&bytes[..]);
    let mut seen = Vec::new();
    while let Some(p) = r.next_packet().unwrap() {
        assert_eq!(p.link_type, LINKTYPE_ETHERNET);
        assert!(p.time.unwrap() >= start);
        seen.push((p.direction.unwrap(), p.data.to_vec()));
    }
    assert_eq!(
        seen,
        [
            (Direction::Inbound, BRD.to_vec()),
            (Direction::Outbound, expected.to_vec())
        ]
    );
    assert_eq!(r.interfaces_seen()[0].name.as_deref(), Some(&*link.slave));
}
