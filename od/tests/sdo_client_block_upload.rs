//! The SDO client against scripted server frames: block upload, and timeouts, aborts and unexpected
//! frames. The frames are written from the layouts of CiA 301 §7.2.4.3; `sdo_client_helpers` lists the
//! command bytes used.

mod sdo_client_helpers;

use od::sdo::{ClientConfig, ClientEvent, SdoClientError};
use od::AbortCode;
use sdo_client_helpers::*;
use std::time::Duration;

// ---- Block upload ----------------------------------------------------------------------------

#[test]
fn block_upload_of_20_bytes_with_crc() {
    let data = twenty();
    let (lo, hi) = crc_bytes(&data);
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_upload(b.now, DOMAIN).unwrap();
    expect(b.sent(), &["A4 00 20 01 7F 00 00 00"]);
    // scs 6, sc 1, s 1, ss 0; size 20.
    b.server("C6 00 20 01 14 00 00 00");
    expect(b.sent(), &["A3 00 00 00 00 00 00 00"]);
    b.server(&seg(0x01, &data[0..7]));
    b.server(&seg(0x02, &data[7..14]));
    assert!(b.sent().is_empty(), "no ack inside the sub-block");
    b.server(&seg(0x83, &data[14..20]));
    // ackseq 3, blksize 127.
    expect(b.sent(), &["A2 03 7F 00 00 00 00 00"]);
    // scs 6, n 1, ss 1.
    b.server(&hex(&[0xC5, lo, hi, 0, 0, 0, 0, 0]));
    expect(b.sent(), &["A1 00 00 00 00 00 00 00"]);
    let events = b.events();
    assert_eq!(progress(&events).last(), Some(&(20, Some(20))));
    match events.last() {
        Some(ClientEvent::Uploaded(got)) => assert_eq!(got, &data),
        other => panic!("{other:?}"),
    }
}

#[test]
fn block_upload_with_a_small_block_size_and_a_lost_segment() {
    let data = twenty();
    let (lo, hi) = crc_bytes(&data);
    let mut b = Bench::new(ClientConfig {
        block_size: 2,
        ..ClientConfig::default()
    });
    b.client.start_upload(b.now, DOMAIN).unwrap();
    expect(b.sent(), &["A4 00 20 01 02 00 00 00"]);
    b.server("C6 00 20 01 14 00 00 00");
    expect(b.sent(), &["A3 00 00 00 00 00 00 00"]);
    // Segment 1 is lost; segment 2 ends the sub-block.
    b.server(&seg(0x02, &data[7..14]));
    expect(b.sent(), &["A2 00 02 00 00 00 00 00"]);
    b.server(&seg(0x01, &data[0..7]));
    b.server(&seg(0x02, &data[7..14]));
    expect(b.sent(), &["A2 02 02 00 00 00 00 00"]);
    b.server(&seg(0x81, &data[14..20]));
    expect(b.sent(), &["A2 01 02 00 00 00 00 00"]);
    b.server(&hex(&[0xC5, lo, hi, 0, 0, 0, 0, 0]));
    expect(b.sent(), &["A1 00 00 00 00 00 00 00"]);
    assert_uploaded(b.outcome(), &data);
}

#[test]
fn block_upload_gap_before_the_last_segment() {
    let data = twenty();
    let (lo, hi) = crc_bytes(&data);
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("C6 00 20 01 14 00 00 00");
    b.sent();
    b.server(&seg(0x01, &data[0..7]));
    // Segment 2 is lost; the last one arrives out of order and ends the sub-block: ackseq 1.
    b.server(&seg(0x83, &data[14..20]));
    expect(b.sent(), &["A2 01 7F 00 00 00 00 00"]);
    b.server(&seg(0x01, &data[7..14]));
    b.server(&seg(0x82, &data[14..20]));
    expect(b.sent(), &["A2 02 7F 00 00 00 00 00"]);
    b.server(&hex(&[0xC5, lo, hi, 0, 0, 0, 0, 0]));
    expect(b.sent(), &["A1 00 00 00 00 00 00 00"]);
    assert_uploaded(b.outcome(), &data);
}

#[test]
fn block_upload_crc_error() {
    let data = twenty();
    let (lo, hi) = crc_bytes(&data);
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("C6 00 20 01 14 00 00 00");
    b.sent();
    b.server(&seg(0x01, &data[0..7]));
    b.server(&seg(0x02, &data[7..14]));
    b.server(&seg(0x83, &data[14..20]));
    b.sent();
    b.server(&hex(&[0xC5, lo ^ 1, hi, 0, 0, 0, 0, 0]));
    expect(b.sent(), &["80 00 20 01 04 00 04 05"]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::CrcError, false);
}

#[test]
fn block_upload_without_crc_ignores_the_crc_field() {
    let data = twenty();
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    // sc 0, s 1.
    b.server("C2 00 20 01 14 00 00 00");
    b.sent();
    b.server(&seg(0x01, &data[0..7]));
    b.server(&seg(0x02, &data[7..14]));
    b.server(&seg(0x83, &data[14..20]));
    b.sent();
    b.server("C5 00 00 00 00 00 00 00");
    expect(b.sent(), &["A1 00 00 00 00 00 00 00"]);
    assert_uploaded(b.outcome(), &data);
}

#[test]
fn block_upload_checks_n_against_the_size() {
    let data = twenty();
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("C6 00 20 01 14 00 00 00");
    b.sent();
    b.server(&seg(0x01, &data[0..7]));
    b.server(&seg(0x02, &data[7..14]));
    b.server(&seg(0x83, &data[14..20]));
    b.sent();
    // n 2 makes 19 bytes where 20 were announced: 0x06070013.
    let (lo, hi) = crc_bytes(&data[..19]);
    b.server(&hex(&[0xC9, lo, hi, 0, 0, 0, 0, 0]));
    expect(b.sent(), &["80 00 20 01 13 00 07 06"]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::LengthTooLow, false);
}

#[test]
fn block_upload_protocol_switch_to_expedited() {
    let mut b = Bench::new(ClientConfig {
        pst: 10,
        ..ClientConfig::default()
    });
    b.client.start_upload(b.now, HEARTBEAT).unwrap();
    // blksize 127, pst 10.
    expect(b.sent(), &["A4 17 10 00 7F 0A 00 00"]);
    // The server answers with a normal expedited initiate upload response of two bytes.
    b.server("4B 17 10 00 E8 03 00 00");
    assert!(b.sent().is_empty());
    assert_uploaded(b.outcome(), &[0xE8, 0x03]);
}

#[test]
fn block_upload_protocol_switch_to_segmented() {
    let mut b = Bench::new(ClientConfig {
        pst: 10,
        ..ClientConfig::default()
    });
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("41 00 20 01 09 00 00 00");
    expect(b.sent(), &["60 00 00 00 00 00 00 00"]);
    b.server("00 31 32 33 34 35 36 37");
    expect(b.sent(), &["70 00 00 00 00 00 00 00"]);
    b.server("1B 38 39 00 00 00 00 00");
    assert!(b.sent().is_empty());
    assert_uploaded(b.outcome(), b"123456789");
}

#[test]
fn block_upload_bad_sequence_numbers() {
    let mut b = Bench::new(ClientConfig {
        block_size: 4,
        ..ClientConfig::default()
    });
    for bad in ["00 01 02 03 04 05 06 07", "05 01 02 03 04 05 06 07"] {
        b.client.start_upload(b.now, DOMAIN).unwrap();
        b.sent();
        b.server("C6 00 20 01 14 00 00 00");
        b.sent();
        // Sequence number 0, or beyond the block size of 4: 0x05040003.
        b.server(bad);
        expect(b.sent(), &["80 00 20 01 03 00 04 05"]);
        assert_aborted(b.outcome(), DOMAIN, AbortCode::InvalidSequence, false);
    }
}

#[test]
fn server_abort_during_a_block_upload_sub_block() {
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("C6 00 20 01 14 00 00 00");
    b.sent();
    b.server(&seg(0x01, &[1; 7]));
    // Byte 0 = 0x80 is an abort (a segment has sequence number 1–127).
    b.server("80 00 20 01 00 00 06 06");
    assert!(b.sent().is_empty());
    assert_aborted(b.outcome(), DOMAIN, AbortCode::HardwareError, true);
}

// ---- Timeouts, aborts, unexpected frames ------------------------------------------------------

#[test]
fn timeout_aborts_on_the_wire() {
    let mut b = Bench::new(ClientConfig::default());
    b.client
        .start_download(b.now, HEARTBEAT, 1000u16.to_le_bytes())
        .unwrap();
    b.sent();
    assert_eq!(b.client.poll_timeout(), Some(b.t0 + Duration::from_secs(1)));
    b.advance(999);
    assert!(b.sent().is_empty());
    assert!(b.client.is_busy());
    b.advance(1);
    expect(b.sent(), &["80 17 10 00 00 00 04 05"]);
    assert_aborted(b.outcome(), HEARTBEAT, AbortCode::Timeout, false);
    // A late answer is ignored.
    b.server("60 17 10 00 00 00 00 00");
    assert!(b.sent().is_empty());
    assert!(b.events().is_empty());
}

#[test]
fn each_answer_restarts_the_timer() {
    let mut b = Bench::new(ClientConfig {
        timeout: Duration::from_millis(100),
        block: false,
        ..ClientConfig::default()
    });
    b.client.start_download(b.now, DOMAIN, twenty()).unwrap();
    b.sent();
    b.advance(90);
    b.server("60 00 20 01 00 00 00 00");
    assert_eq!(
        b.client.poll_timeout(),
        Some(b.t0 + Duration::from_millis(190))
    );
    b.advance(90);
    b.server("20 00 00 00 00 00 00 00");
    b.advance(99);
    assert!(b.client.is_busy());
    b.advance(1);
    b.sent();
    let e = b.outcome();
    assert_aborted(e, DOMAIN, AbortCode::Timeout, false);
}

#[test]
fn timeout_of_a_block_upload_sub_block() {
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("C6 00 20 01 14 00 00 00");
    b.sent();
    b.advance(500);
    b.server(&seg(0x01, &[1; 7]));
    b.advance(999);
    assert!(b.sent().is_empty());
    b.advance(1);
    expect(b.sent(), &["80 00 20 01 00 00 04 05"]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::Timeout, false);
}

#[test]
fn a_block_initiate_that_times_out_does_not_fall_back() {
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_download(b.now, DOMAIN, twenty()).unwrap();
    b.sent();
    b.advance(1000);
    expect(b.sent(), &["80 00 20 01 00 00 04 05"]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::Timeout, false);
}

#[test]
fn server_abort_ends_the_transfer() {
    let mut b = Bench::new(ClientConfig::default());
    b.client
        .start_download(b.now, HEARTBEAT, 1000u16.to_le_bytes())
        .unwrap();
    b.sent();
    // 0x06010002: read-only.
    b.server("80 17 10 00 02 00 01 06");
    assert!(b.sent().is_empty(), "an abort is not answered");
    assert_aborted(b.outcome(), HEARTBEAT, AbortCode::ReadOnly, true);
}

#[test]
fn server_abort_with_an_unknown_code() {
    let mut b = Bench::segmented();
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("80 00 20 01 78 56 34 12");
    assert_aborted(b.outcome(), DOMAIN, AbortCode::Unknown(0x1234_5678), true);
}

#[test]
fn unexpected_frames_are_aborted_with_0x05040001() {
    // A response for another entry.
    let mut b = Bench::new(ClientConfig::default());
    b.client
        .start_download(b.now, HEARTBEAT, 1000u16.to_le_bytes())
        .unwrap();
    b.sent();
    b.server("60 18 10 00 00 00 00 00");
    expect(b.sent(), &["80 17 10 00 01 00 04 05"]);
    assert_aborted(b.outcome(), HEARTBEAT, AbortCode::InvalidCommand, false);

    // An upload response to a download.
    b.client
        .start_download(b.now, HEARTBEAT, 1000u16.to_le_bytes())
        .unwrap();
    b.sent();
    b.server("4B 17 10 00 E8 03 00 00");
    expect(b.sent(), &["80 17 10 00 01 00 04 05"]);
    assert_aborted(b.outcome(), HEARTBEAT, AbortCode::InvalidCommand, false);

    // An unknown command specifier (scs 7).
    b.client.start_upload(b.now, HEARTBEAT).unwrap();
    b.sent();
    b.server("E0 17 10 00 00 00 00 00");
    expect(b.sent(), &["80 17 10 00 01 00 04 05"]);
    assert_aborted(b.outcome(), HEARTBEAT, AbortCode::InvalidCommand, false);

    // A block download ack in a segmented download.
    let mut b = Bench::segmented();
    b.client.start_download(b.now, DOMAIN, twenty()).unwrap();
    b.sent();
    b.server("60 00 20 01 00 00 00 00");
    b.sent();
    b.server("A2 01 7F 00 00 00 00 00");
    expect(b.sent(), &["80 00 20 01 01 00 04 05"]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::InvalidCommand, false);
}

#[test]
fn frames_while_idle_are_ignored() {
    let mut b = Bench::new(ClientConfig::default());
    for f in [
        "60 17 10 00 00 00 00 00",
        "80 17 10 00 00 00 04 05",
        "FF FF FF FF FF FF FF FF",
    ] {
        b.server(f);
    }
    b.advance(10_000);
    assert!(b.sent().is_empty());
    assert!(b.events().is_empty());
    assert_eq!(b.client.poll_timeout(), None);
}

#[test]
fn starting_while_busy_is_refused() {
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_upload(b.now, DOMAIN).unwrap();
    assert!(matches!(
        b.client.start_download(b.now, HEARTBEAT, [1, 2]),
        Err(SdoClientError::Busy)
    ));
    assert!(matches!(
        b.client.start_upload(b.now, HEARTBEAT),
        Err(SdoClientError::Busy)
    ));
    // The running transfer is untouched.
    expect(b.sent(), &["A4 00 20 01 7F 00 00 00"]);
    assert!(b.client.is_busy());
}

#[test]
fn local_abort() {
    let mut b = Bench::new(ClientConfig::default());
    assert!(!b.client.abort(AbortCode::General));
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    assert!(b.client.abort(AbortCode::LocalControl));
    expect(b.sent(), &["80 00 20 01 21 00 00 08"]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::LocalControl, false);
}

#[test]
fn an_abort_drops_the_unsent_rest_of_a_sub_block() {
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_download(b.now, DOMAIN, twenty()).unwrap();
    b.sent();
    b.server("A4 00 20 01 7F 00 00 00");
    // One segment went out, then the server aborts.
    assert!(b.client.poll_transmit().is_some());
    b.server("80 00 20 01 00 00 00 08");
    assert!(b.sent().is_empty());
    assert_aborted(b.outcome(), DOMAIN, AbortCode::General, true);
}
