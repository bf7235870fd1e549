//! The LSS master frame by frame: every request's bytes as CiA 305 §8 lays them out (command
//! specifier in byte 0, values little-endian from byte 1), worked out by hand, and the outcome of
//! each answer, refusal and silence.

use std::time::{Duration, Instant};

use can_link::CanFrame;
use canopen_net::lss::{
    AddressPart, LssAddress, LssAnswer, LssError, LssMaster, LssRequest, LssState, PartScan,
};

fn answer(data: [u8; 8]) -> CanFrame {
    CanFrame::new(0x7E4, &data).unwrap()
}

fn sent(master: &mut LssMaster) -> Vec<(u16, [u8; 8])> {
    std::iter::from_fn(|| master.poll_transmit())
        .map(|f| (f.cob_id().unwrap(), f.data8()))
        .collect()
}

fn started(request: LssRequest) -> (LssMaster, Instant, Vec<(u16, [u8; 8])>) {
    let t0 = Instant::now();
    let mut m = LssMaster::new();
    m.start(t0, request).unwrap();
    let frames = sent(&mut m);
    (m, t0, frames)
}

#[test]
fn switch_state_global_is_one_frame_without_answer() {
    let (mut m, _, frames) = started(LssRequest::SwitchGlobal(LssState::Configuration));
    assert_eq!(frames, [(0x7E5, [0x04, 0x01, 0, 0, 0, 0, 0, 0])]);
    assert_eq!(m.poll_event(), Some(Ok(LssAnswer::Sent)));
    assert_eq!(m.poll_timeout(), None);
    let (mut m, _, frames) = started(LssRequest::SwitchGlobal(LssState::Waiting));
    assert_eq!(frames, [(0x7E5, [0x04, 0x00, 0, 0, 0, 0, 0, 0])]);
    assert_eq!(m.poll_event(), Some(Ok(LssAnswer::Sent)));
}

#[test]
fn switch_state_selective_sends_the_four_parts_and_takes_0x44() {
    let address = [0x0000_005A, 0x0000_0402, 0x0001_0002, 0x1234_5678];
    let (mut m, t0, frames) = started(LssRequest::SwitchSelective(address));
    assert_eq!(
        frames,
        [
            (0x7E5, [0x40, 0x5A, 0x00, 0x00, 0x00, 0, 0, 0]),
            (0x7E5, [0x41, 0x02, 0x04, 0x00, 0x00, 0, 0, 0]),
            (0x7E5, [0x42, 0x02, 0x00, 0x01, 0x00, 0, 0, 0]),
            (0x7E5, [0x43, 0x78, 0x56, 0x34, 0x12, 0, 0, 0]),
        ]
    );
    assert_eq!(m.poll_timeout(), Some(t0 + Duration::from_millis(100)));
    // Not the answer: another COB-ID, another length, another command specifier.
    m.handle_frame(
        t0,
        &CanFrame::new(0x7E5, &[0x44, 0, 0, 0, 0, 0, 0, 0]).unwrap(),
    );
    m.handle_frame(t0, &CanFrame::new(0x7E4, &[0x44]).unwrap());
    m.handle_frame(t0, &answer([0x4F, 0, 0, 0, 0, 0, 0, 0]));
    assert_eq!(m.poll_event(), None);
    m.handle_frame(t0, &answer([0x44, 0, 0, 0, 0, 0, 0, 0]));
    assert_eq!(m.poll_event(), Some(Ok(LssAnswer::Selected)));
    assert!(!m.is_busy());
}

#[test]
fn configure_node_id_done_and_refused() {
    let (mut m, t0, frames) = started(LssRequest::ConfigureNodeId(10));
    assert_eq!(frames, [(0x7E5, [0x11, 0x0A, 0, 0, 0, 0, 0, 0])]);
    m.handle_frame(t0, &answer([0x11, 0x00, 0, 0, 0, 0, 0, 0]));
    assert_eq!(m.poll_event(), Some(Ok(LssAnswer::Done)));

    let (mut m, t0, _) = started(LssRequest::ConfigureNodeId(0xFF));
    m.handle_frame(t0, &answer([0x11, 0x01, 0, 0, 0, 0, 0, 0]));
    let e = m.poll_event().unwrap().unwrap_err();
    assert_eq!(
        e.to_string(),
        "configure node-ID: refused with error code 1 (out of range or not supported)"
    );

    let (mut m, t0, _) = started(LssRequest::ConfigureNodeId(5));
    m.handle_frame(t0, &answer([0x11, 0xFF, 0x07, 0, 0, 0, 0, 0]));
    assert_eq!(
        m.poll_event(),
        Some(Err(LssError::Refused {
            service: "configure node-ID",
            code: 0xFF,
            specific: 7
        }))
    );
    assert_eq!(
        LssError::Refused {
            service: "store configuration",
            code: 0xFF,
            specific: 7
        }
        .to_string(),
        "store configuration: refused with error code 255 (manufacturer-specific error 0x07)"
    );

    let mut m = LssMaster::new();
    let e = m.start(t0, LssRequest::ConfigureNodeId(0)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "configure node-ID: node-ID 0 is not 1 to 127 or 0xFF"
    );
    assert_eq!(sent(&mut m), []);
}

#[test]
fn bit_timing_store_and_activate() {
    let (mut m, t0, frames) = started(LssRequest::ConfigureBitTiming { table: 0, index: 4 });
    assert_eq!(frames, [(0x7E5, [0x13, 0x00, 0x04, 0, 0, 0, 0, 0])]);
    m.handle_frame(t0, &answer([0x13, 0x00, 0, 0, 0, 0, 0, 0]));
    assert_eq!(m.poll_event(), Some(Ok(LssAnswer::Done)));

    let (mut m, t0, frames) = started(LssRequest::Store);
    assert_eq!(frames, [(0x7E5, [0x17, 0, 0, 0, 0, 0, 0, 0])]);
    m.handle_frame(t0, &answer([0x17, 0x01, 0, 0, 0, 0, 0, 0]));
    assert_eq!(
        m.poll_event().unwrap().unwrap_err().to_string(),
        "store configuration: refused with error code 1 (out of range or not supported)"
    );

    let (mut m, _, frames) = started(LssRequest::ActivateBitTiming { delay_ms: 1000 });
    assert_eq!(frames, [(0x7E5, [0x15, 0xE8, 0x03, 0, 0, 0, 0, 0])]);
    assert_eq!(m.poll_event(), Some(Ok(LssAnswer::Sent)));
}

#[test]
fn inquire_identity_and_node_id() {
    let codes = [0x5A, 0x5B, 0x5C, 0x5D];
    for (part, code) in AddressPart::ALL.into_iter().zip(codes) {
        let (mut m, t0, frames) = started(LssRequest::Inquire(part));
        assert_eq!(frames, [(0x7E5, [code, 0, 0, 0, 0, 0, 0, 0])]);
        m.handle_frame(t0, &answer([code, 0x78, 0x56, 0x34, 0x12, 0, 0, 0]));
        assert_eq!(m.poll_event(), Some(Ok(LssAnswer::Value(0x1234_5678))));
    }
    let (mut m, t0, frames) = started(LssRequest::InquireNodeId);
    assert_eq!(frames, [(0x7E5, [0x5E, 0, 0, 0, 0, 0, 0, 0])]);
    m.handle_frame(t0, &answer([0x5E, 0xFF, 0, 0, 0, 0, 0, 0]));
    assert_eq!(m.poll_event(), Some(Ok(LssAnswer::NodeId(0xFF))));
}

#[test]
fn silence_is_a_timeout_and_a_second_service_waits() {
    let (mut m, t0, _) = started(LssRequest::InquireNodeId);
    assert_eq!(
        m.start(t0, LssRequest::Store),
        Err(LssError::Busy {
            service: "store configuration"
        })
    );
    m.handle_timeout(t0 + Duration::from_millis(99));
    assert_eq!(m.poll_event(), None);
    m.handle_timeout(t0 + Duration::from_millis(100));
    let e = m.poll_event().unwrap().unwrap_err();
    assert_eq!(e.to_string(), "inquire node-ID: no answer within 100 ms");
    // A late answer is nothing to the master.
    m.handle_frame(t0, &answer([0x5E, 0x05, 0, 0, 0, 0, 0, 0]));
    assert_eq!(m.poll_event(), None);
}

#[test]
fn identify_remote_and_non_configured_slaves() {
    let (mut m, t0, frames) = started(LssRequest::IdentifyRemote {
        vendor: 0x5A,
        product: 0x402,
        revision: (0, 0xFFFF_FFFF),
        serial: (1, 3),
    });
    assert_eq!(
        frames,
        [
            (0x7E5, [0x46, 0x5A, 0, 0, 0, 0, 0, 0]),
            (0x7E5, [0x47, 0x02, 0x04, 0, 0, 0, 0, 0]),
            (0x7E5, [0x48, 0, 0, 0, 0, 0, 0, 0]),
            (0x7E5, [0x49, 0xFF, 0xFF, 0xFF, 0xFF, 0, 0, 0]),
            (0x7E5, [0x4A, 0x01, 0, 0, 0, 0, 0, 0]),
            (0x7E5, [0x4B, 0x03, 0, 0, 0, 0, 0, 0]),
        ]
    );
    m.handle_frame(t0, &answer([0x4F, 0, 0, 0, 0, 0, 0, 0]));
    assert_eq!(m.poll_event(), Some(Ok(LssAnswer::Identified(true))));

    let (mut m, t0, frames) = started(LssRequest::IdentifyNonConfigured);
    assert_eq!(frames, [(0x7E5, [0x4C, 0, 0, 0, 0, 0, 0, 0])]);
    m.handle_timeout(t0 + Duration::from_millis(100));
    assert_eq!(m.poll_event(), Some(Ok(LssAnswer::Identified(false))));
}

/// A slave as CiA 305 §8.4.2.4 has it answer Fastscan: in the waiting state without a node-ID, it
/// answers 0x80; otherwise when `sub` is the part it is at and the bits of the part from
/// `bit_checked` up equal IDNumber's; a match at bit 0 moves it to part `next`, and after the
/// last part to the configuration state.
struct Slave {
    address: LssAddress,
    at: u8,
    configuration: bool,
}

impl Slave {
    fn answers(&mut self, d: [u8; 8]) -> bool {
        if d[0] != 0x51 || self.configuration {
            return false;
        }
        let (id, bit, sub, next) = (
            u32::from_le_bytes([d[1], d[2], d[3], d[4]]),
            d[5],
            d[6],
            d[7],
        );
        if bit == 0x80 {
            self.at = 0;
            return true;
        }
        if sub != self.at || (id ^ self.address[usize::from(sub)]) >> bit != 0 {
            return false;
        }
        if bit == 0 {
            if next < sub {
                self.configuration = true;
            }
            self.at = next;
        }
        true
    }
}

/// Runs a Fastscan among `slaves`, each request answered at once by every slave that matches (a
/// frame each), silence taking the full 100 ms. Returns the outcome, the requests
/// and the time taken.
fn fastscan(slaves: &mut [Slave]) -> (Result<LssAnswer, LssError>, Vec<[u8; 8]>, Duration) {
    fastscan_with(slaves, LssRequest::Fastscan)
}

/// [`fastscan`] with `request` (a Fastscan with parts matched or skipped).
fn fastscan_with(
    slaves: &mut [Slave],
    request: LssRequest,
) -> (Result<LssAnswer, LssError>, Vec<[u8; 8]>, Duration) {
    let t0 = Instant::now();
    let mut now = t0;
    let mut m = LssMaster::new();
    m.start(now, request).unwrap();
    let mut requests = Vec::new();
    for _ in 0..10_000 {
        while let Some(f) = m.poll_transmit() {
            assert_eq!(f.cob_id(), Some(0x7E5));
            requests.push(f.data8());
            // Each slave that matches answers: the copies come one after the other.
            for s in slaves.iter_mut() {
                if s.answers(f.data8()) {
                    m.handle_frame(now, &answer([0x4F, 0, 0, 0, 0, 0, 0, 0]));
                }
            }
        }
        if let Some(outcome) = m.poll_event() {
            return (outcome, requests, now - t0);
        }
        now = m.poll_timeout().unwrap();
        m.handle_timeout(now);
    }
    panic!("the Fastscan did not end: {} requests", requests.len());
}

#[test]
fn fastscan_finds_the_lowest_address_bit_by_bit() {
    let a = [0x0000_005A, 0x0000_0402, 0x0000_0001, 0x0000_0003];
    let b = [0x0000_005A, 0x0000_0402, 0x0000_0001, 0x0000_0002];
    let mut slaves = [a, b].map(|address| Slave {
        address,
        at: 0,
        configuration: false,
    });
    let (outcome, requests, _) = fastscan(&mut slaves);
    assert_eq!(outcome, Ok(LssAnswer::Found(b)));
    assert!(!slaves[0].configuration && slaves[1].configuration);
    // The start, then per part 32 bits and the confirmation.
    assert_eq!(requests.len(), 1 + 4 * 33);
    assert_eq!(requests[0], [0x51, 0, 0, 0, 0, 0x80, 0, 0]);
    // Bit 31 of the vendor-ID, asked as 0 (LSSSub 0, LSSNext 0).
    assert_eq!(requests[1], [0x51, 0, 0, 0, 0, 0x1F, 0, 0]);
    // Bits 6, 4, 3 and 1 of 0x5A are 1: each was asked as 0 and met silence.
    assert_eq!(requests[26], [0x51, 0x00, 0, 0, 0, 0x06, 0, 0]);
    assert_eq!(requests[27], [0x51, 0x40, 0, 0, 0, 0x05, 0, 0]);
    assert_eq!(requests[32], [0x51, 0x5A, 0, 0, 0, 0x00, 0, 0]);
    // The vendor-ID confirmed, LSSNext 1; the product code's bits asked with LSSSub 1, LSSNext 1.
    assert_eq!(requests[33], [0x51, 0x5A, 0, 0, 0, 0x00, 0, 1]);
    assert_eq!(requests[34], [0x51, 0, 0, 0, 0, 0x1F, 1, 1]);
    assert_eq!(requests[66], [0x51, 0x02, 0x04, 0, 0, 0x00, 1, 2]);
    assert_eq!(requests[99], [0x51, 0x01, 0, 0, 0, 0x00, 2, 3]);
    // The serial number confirmed with LSSNext 0: the slave goes to the configuration state.
    assert_eq!(requests[132], [0x51, 0x02, 0, 0, 0, 0x00, 3, 0]);

    // The second scan finds the other slave; the third finds none.
    let (outcome, _, _) = fastscan(&mut slaves);
    assert_eq!(outcome, Ok(LssAnswer::Found(a)));
    let (outcome, requests, took) = fastscan(&mut slaves);
    assert_eq!(outcome, Ok(LssAnswer::NotFound));
    assert_eq!(requests, [[0x51, 0, 0, 0, 0, 0x80, 0, 0]]);
    assert_eq!(took, Duration::from_millis(100));
}

#[test]
fn fastscan_without_a_confirmation_starts_again_twice_then_is_an_error() {
    let mut m = LssMaster::with_timeout(Duration::from_millis(10));
    let t0 = Instant::now();
    m.start(t0, LssRequest::Fastscan).unwrap();
    m.handle_frame(t0, &answer([0x4F, 0, 0, 0, 0, 0, 0, 0]));
    // Every bit of the vendor-ID meets silence (all ones), and so does the confirmation; the scan
    // starts again after a quiet 10 ms with 20 ms a step, meets silence, and again after a quiet
    // 20 ms with 40 ms.
    let mut requests: Vec<(Duration, [u8; 8])> = Vec::new();
    let mut now = t0;
    let mut calls = 0;
    let outcome = loop {
        calls += 1;
        assert!(calls < 10_000, "the Fastscan did not end");
        requests.extend(std::iter::from_fn(|| m.poll_transmit()).map(|f| (now - t0, f.data8())));
        if let Some(o) = m.poll_event() {
            break o;
        }
        now = m.poll_timeout().unwrap();
        m.handle_timeout(now);
    };
    assert_eq!(
        outcome.unwrap_err().to_string(),
        "Fastscan: no slave confirmed the vendor-ID 0xFFFFFFFF"
    );
    let ms = Duration::from_millis;
    assert_eq!(requests.len(), 1 + 33 + 2);
    // The first bit after the settling time of the start's answer (a tenth of the bound).
    let expected = [
        (1, ms(1), [0x51, 0, 0, 0, 0, 31, 0, 0]),
        (32, ms(311), [0x51, 0xFE, 0xFF, 0xFF, 0xFF, 0, 0, 0]),
        (33, ms(321), [0x51, 0xFF, 0xFF, 0xFF, 0xFF, 0, 0, 1]),
        (34, ms(341), [0x51, 0, 0, 0, 0, 0x80, 0, 0]),
        (35, ms(381), [0x51, 0, 0, 0, 0, 0x80, 0, 0]),
    ];
    for (i, at, frame) in expected {
        assert_eq!(requests[i], (at, frame), "request {i}");
    }
    assert_eq!(now - t0, ms(421));
    assert!(!m.is_busy());
}

/// A Fastscan of `slave` whose answer to request `i` (from 0) comes `delay(i)` after it (a busy
/// gateway or machine), with `timeout` a step: the outcome and the starts (requests with
/// `BitChecked` 0x80).
fn late_fastscan(
    slave: &mut Slave,
    delay: impl Fn(usize) -> Duration,
    timeout: Duration,
) -> (Result<LssAnswer, LssError>, usize) {
    let t0 = Instant::now();
    let mut now = t0;
    let mut m = LssMaster::with_timeout(timeout);
    m.start(now, LssRequest::Fastscan).unwrap();
    let mut due: Vec<Instant> = Vec::new();
    let mut starts = 0;
    let mut sent = 0;
    for _ in 0..10_000 {
        while let Some(f) = m.poll_transmit() {
            starts += usize::from(f.data8()[5] == 0x80);
            if slave.answers(f.data8()) {
                due.push(now + delay(sent));
            }
            sent += 1;
        }
        if let Some(outcome) = m.poll_event() {
            return (outcome, starts);
        }
        let next_answer = due.iter().min().copied();
        let timer = m.poll_timeout().unwrap();
        match next_answer {
            Some(t) if t <= timer => {
                now = t;
                due.retain(|&d| d != t);
                m.handle_frame(now, &answer([0x4F, 0, 0, 0, 0, 0, 0, 0]));
            }
            _ => {
                now = timer;
                m.handle_timeout(now);
            }
        }
    }
    panic!("the Fastscan did not end");
}

#[test]
fn a_slave_answering_later_than_the_bound_is_found_when_the_scan_starts_again() {
    let address = [0x0000_0ABC, 0x0000_0402, 0x0001_0001, 0x0000_0002];
    let mut slave = Slave {
        address,
        at: 0,
        configuration: false,
    };
    // Requests 5 to 9 answered 15 ms late with 10 ms a step, the others at once: an answer is
    // taken for the next step, the vendor-ID is not confirmed; started again, it is found.
    let hiccup = |i: usize| Duration::from_millis(if (5..10).contains(&i) { 15 } else { 0 });
    let (outcome, starts) = late_fastscan(&mut slave, hiccup, Duration::from_millis(10));
    assert_eq!(outcome.unwrap(), LssAnswer::Found(address));
    assert_eq!(starts, 2);
    assert!(slave.configuration);
    // In time: one start.
    let mut slave = Slave {
        address,
        at: 0,
        configuration: false,
    };
    let in_time = |_| Duration::from_millis(5);
    let (outcome, starts) = late_fastscan(&mut slave, in_time, Duration::from_millis(10));
    assert_eq!((outcome.unwrap(), starts), (LssAnswer::Found(address), 1));
}

#[test]
fn fastscan_takes_the_copies_of_an_answer_as_one() {
    let t0 = Instant::now();
    let mut m = LssMaster::new();
    m.start(t0, LssRequest::Fastscan).unwrap();
    assert_eq!(
        m.poll_transmit().unwrap().data8(),
        [0x51, 0, 0, 0, 0, 0x80, 0, 0]
    );
    let ms = |n| t0 + Duration::from_millis(n);
    m.handle_frame(ms(1), &answer([0x4F, 0, 0, 0, 0, 0, 0, 0]));
    // The next step waits for the settling time, 10 ms after the first answer.
    assert_eq!(m.poll_transmit(), None);
    assert_eq!(m.poll_timeout(), Some(ms(11)));
    m.handle_frame(ms(3), &answer([0x4F, 0, 0, 0, 0, 0, 0, 0]));
    assert_eq!(m.poll_timeout(), Some(ms(11)));
    m.handle_timeout(ms(11));
    assert_eq!(
        m.poll_transmit().unwrap().data8(),
        [0x51, 0, 0, 0, 0, 0x1F, 0, 0]
    );
    assert_eq!(m.poll_timeout(), Some(ms(111)));
    assert_eq!(m.poll_event(), None);
}

/// Store configuration waits for its answer at least 1 s (the node answers once its non-volatile
/// memory has the configuration), whatever shorter bound the master has for the other services.
#[test]
fn store_configuration_waits_at_least_a_second() {
    let (mut m, t0, _) = started(LssRequest::Store);
    assert_eq!(m.timeout(), Duration::from_millis(100));
    assert_eq!(m.poll_timeout(), Some(t0 + Duration::from_secs(1)));
    m.handle_timeout(t0 + Duration::from_millis(999));
    assert_eq!(m.poll_event(), None);
    m.handle_timeout(t0 + Duration::from_secs(1));
    let e = m.poll_event().unwrap().unwrap_err();
    assert_eq!(
        e.to_string(),
        "store configuration: no answer within 1000 ms"
    );
    // Answered late but within the second: taken.
    let (mut m, t0, _) = started(LssRequest::Store);
    m.handle_frame(
        t0 + Duration::from_millis(700),
        &answer([0x17, 0, 0, 0, 0, 0, 0, 0]),
    );
    assert_eq!(m.poll_event(), Some(Ok(LssAnswer::Done)));
}

#[test]
fn a_bound_beyond_an_hour_is_cut_to_one() {
    let t0 = Instant::now();
    let mut m = LssMaster::with_timeout(Duration::MAX);
    assert_eq!(m.timeout(), Duration::from_secs(3600));
    m.start(t0, LssRequest::Store).unwrap();
    assert_eq!(m.poll_timeout(), Some(t0 + Duration::from_secs(3600)));
}

mod any_traffic {
    use super::*;
    use proptest::prelude::*;

    fn request(pick: u8, value: u8) -> LssRequest {
        match pick % 8 {
            0 => LssRequest::Fastscan,
            1 => LssRequest::SwitchSelective([u32::from(value); 4]),
            2 => LssRequest::ConfigureNodeId(value),
            3 => LssRequest::Store,
            4 => LssRequest::Inquire(AddressPart::ALL[usize::from(value % 4)]),
            5 => LssRequest::InquireNodeId,
            6 => LssRequest::IdentifyNonConfigured,
            _ => LssRequest::ConfigureBitTiming {
                table: 0,
                index: value,
            },
        }
    }

    proptest! {
        /// Any frames at any times, answers or not, never panic; every service ends, with an
        /// answer or an error, once the time passes its bound.
        #[test]
        fn every_service_ends_whatever_comes(
            pick in any::<u8>(),
            value in any::<u8>(),
            traffic in proptest::collection::vec(
                (0x7E0u16..0x7E8, proptest::collection::vec(any::<u8>(), 0..9), 0u64..30),
                0..200,
            ),
        ) {
            let t0 = Instant::now();
            let mut m = LssMaster::new();
            if m.start(t0, request(pick, value)).is_err() {
                return Ok(());
            }
            let mut now = t0;
            let mut ended = false;
            for (cob, data, step) in traffic {
                now += Duration::from_millis(step);
                m.handle_frame(now, &CanFrame::new(cob, &data).unwrap());
                m.handle_timeout(now);
                while m.poll_transmit().is_some() {}
                ended |= m.poll_event().is_some();
            }
            // A Fastscan takes at most 1 + 4 × 33 steps of a bound each.
            for _ in 0..200 {
                if ended {
                    break;
                }
                if let Some(t) = m.poll_timeout() {
                    m.handle_timeout(t);
                }
                ended |= m.poll_event().is_some();
            }
            prop_assert!(ended);
            prop_assert!(!m.is_busy());
        }
    }
}

#[test]
fn fastscan_matches_known_parts_at_once_and_skips_others() {
    let a = [0x0000_0ABC, 0x0000_0402, 0x0001_0001, 0x0000_0002];
    let b = [0x0000_0ABC, 0x0000_0402, 0x0001_0001, 0x0000_0007];
    let mut slaves = [
        Slave {
            address: b,
            at: 0,
            configuration: false,
        },
        Slave {
            address: a,
            at: 0,
            configuration: false,
        },
    ];
    // Vendor and product matched, revision scanned, serial skipped: the confirmation of the
    // revision names part 0 next, which ends the scan for the slave that matches it.
    let parts = [
        PartScan::Match(0xABC),
        PartScan::Match(0x402),
        PartScan::Scan,
        PartScan::Skip,
    ];
    let (outcome, requests, _) = fastscan_with(&mut slaves, LssRequest::FastscanWith(parts));
    assert_eq!(
        outcome.unwrap(),
        LssAnswer::Found([0xABC, 0x402, 0x0001_0001, 0])
    );
    assert_eq!(requests.len(), 1 + 2 + 32 + 1);
    assert_eq!(requests[1], [0x51, 0xBC, 0x0A, 0, 0, 0, 0, 1]);
    assert_eq!(requests[2], [0x51, 0x02, 0x04, 0, 0, 0, 1, 2]);
    assert_eq!(requests[3], [0x51, 0, 0, 0, 0, 31, 2, 2]);
    assert_eq!(requests[35], [0x51, 0x01, 0x00, 0x01, 0x00, 0, 2, 0]);
    // Both slaves match all it asked: both are in the configuration state (serials not looked at).
    assert!(slaves.iter().all(|s| s.configuration));
    // A vendor-ID that does not match: no confirmation, and the scan is lost.
    let mut slaves = [Slave {
        address: a,
        at: 0,
        configuration: false,
    }];
    let parts = [
        PartScan::Match(0x5A),
        PartScan::Scan,
        PartScan::Scan,
        PartScan::Scan,
    ];
    let (outcome, _, _) = fastscan_with(&mut slaves, LssRequest::FastscanWith(parts));
    assert_eq!(
        outcome.unwrap_err().to_string(),
        "Fastscan: no slave confirmed the vendor-ID 0x0000005A"
    );
    // Skipping the vendor-ID scans it.
    let mut slaves = [Slave {
        address: a,
        at: 0,
        configuration: false,
    }];
    let parts = [
        PartScan::Skip,
        PartScan::Scan,
        PartScan::Scan,
        PartScan::Scan,
    ];
    let (outcome, _, _) = fastscan_with(&mut slaves, LssRequest::FastscanWith(parts));
    assert_eq!(outcome.unwrap(), LssAnswer::Found(a));
}
