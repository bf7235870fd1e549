//! A raw socket's frames in a capture: two sockets on the two ends of a veth pair in a network
//! namespace of the test's own (the thread's: it goes with the thread), each frame sent one at a time
//! and in a batch, received one at a time and in a batch, recorded in order with its direction.
//! Needs root (a network namespace, a veth pair, raw sockets).

use std::process::Command;
use std::time::{Duration, SystemTime};

use ecat_link::raw::{Batch, RawSocket};
use link_capture::pcapng::{Direction, Reader, LINKTYPE_ETHERNET};
use link_capture::Capture;

/// An EtherCAT frame of `len` bytes with `tag` in its last byte.
fn frame(len: usize, tag: u8) -> Vec<u8> {
    let mut f = vec![0u8; len];
    f[..6].fill(0xFF);
    f[6..12].copy_from_slice(&[0x02, 0, 0, 0, 0, 0x01]);
    f[12..14].copy_from_slice(&[0x88, 0xA4]);
    f[len - 1] = tag;
    f
}

fn ip(args: &[&str]) {
    let o = Command::new("ip").args(args).output().expect("run ip");
    assert!(
        o.status.success(),
        "ip {args:?} (the test needs root): {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Waits for a frame on `s`.
fn wait(s: &RawSocket) {
    assert!(
        s.wait(Duration::from_secs(5)).unwrap(),
        "no frame within 5 s"
    );
}

#[test]
fn frames_sent_and_received_one_at_a_time_and_in_batches_are_captured() {
    std::thread::spawn(|| {
        // SAFETY: unshare(2) with a constant flag; it changes this thread's network namespace only.
        assert_eq!(
            unsafe { libc::unshare(libc::CLONE_NEWNET) },
            0,
            "unshare(CLONE_NEWNET) (the test needs root): {}",
            std::io::Error::last_os_error()
        );
        ip(&[
            "link", "add", "capa", "type", "veth", "peer", "name", "capb",
        ]);
        ip(&["link", "set", "capa", "up"]);
        ip(&["link", "set", "capb", "up"]);
        let (capture, file) = Capture::in_memory("test");
        let mut a = RawSocket::open("capa").unwrap();
        let b = RawSocket::open("capb").unwrap();
        a.capture_to(&capture);
        let start = SystemTime::now();
        // One frame sent, received one at a time on b, answered, received on a.
        a.send(&frame(60, 1)).unwrap();
        let mut buf = [0u8; 1514];
        wait(&b);
        let n = b.recv(&mut buf).unwrap().unwrap();
        assert_eq!(&buf[..n], frame(60, 1));
        b.send(&frame(64, 2)).unwrap();
        wait(&a);
        assert_eq!(a.recv(&mut buf).unwrap(), Some(64));
        // Three in a batch, the middle one skipped: two sent.
        let mut out = Batch::new(3, 1514);
        for tag in [3, 4, 5] {
            assert!(out.push(&frame(60, tag)));
        }
        out.skip(1);
        a.send_batch(&out).unwrap();
        // Three more, the second longer than the link's 1,514 bytes: refused by the kernel, the
        // others sent; only those are in the capture.
        let mut out = Batch::new(3, 4096);
        for (len, tag) in [(60, 8), (3000, 9), (60, 10)] {
            assert!(out.push(&frame(len, tag)));
        }
        assert!(
            a.send_batch(&out).is_err(),
            "a 3,000-byte frame on a 1,500-byte MTU"
        );
        // Two answered, received in a batch on a.
        for tag in [6, 7] {
            b.send(&frame(70, tag)).unwrap();
        }
        let mut got = Batch::new(8, 1514);
        let mut received = 0;
        while received < 2 {
            wait(&a);
            received += a.recv_batch(&mut got).unwrap();
        }
        // The frames of the last batch are held until the socket waits (or is flushed, or
        // dropped): a 70-byte frame is a 116-byte block (8 + 20 + 72 + 8 + 4 + 4).
        let held = file.lock().unwrap().len();
        a.wait(Duration::ZERO).unwrap();
        let written = file.lock().unwrap().len() - held;
        assert!(
            written > 0 && written % 116 == 0,
            "{written} bytes at the wait"
        );
        // A frame sent and not yet written reaches the file when the socket is dropped, the
        // capture still open.
        use std::os::fd::{AsFd, AsRawFd};
        assert_eq!(a.as_raw_fd(), a.as_fd().as_raw_fd());
        assert!(a.as_raw_fd() > 2);
        a.send(&frame(60, 11)).unwrap();
        drop(a);
        let bytes = file.lock().unwrap().clone();
        let mut r = Reader::new(&bytes[..]);
        let mut seen = Vec::new();
        while let Some(p) = r.next_packet().unwrap() {
            assert_eq!(p.link_type, LINKTYPE_ETHERNET);
            assert!(p.time.unwrap() >= start);
            seen.push((p.direction.unwrap(), p.data.len(), p.data[p.data.len() - 1]));
        }
        use Direction::{Inbound as In, Outbound as Out};
        assert_eq!(
            seen,
            [
                (Out, 60, 1),
                (In, 64, 2),
                (Out, 60, 3),
                (Out, 60, 5),
                (Out, 60, 8),
                (Out, 60, 10),
                (In, 70, 6),
                (In, 70, 7),
                (Out, 60, 11)
            ]
        );
        assert_eq!(r.interfaces_seen()[0].name.as_deref(), Some("capa"));
    })
    .join()
    .unwrap();
}
