//! The SDO client against scripted server frames: expedited and segmented transfers, block download and
//! the fall-back from block to segmented transfers. The frames are written from the layouts of CiA 301
//! §7.2.4.3; `sdo_client_helpers` lists the command bytes used.

mod sdo_client_helpers;

use od::sdo::client::WriteSink;
use od::sdo::{Address, ClientConfig, ClientEvent, DownloadData, DownloadSource, UploadSink};
use od::AbortCode;
use sdo_client_helpers::*;
use std::io;
use std::sync::{Arc, Mutex};
use std::time::Duration;

// ---- Expedited -------------------------------------------------------------------------------

#[test]
fn expedited_download_of_a_u16() {
    let mut b = Bench::new(ClientConfig::default());
    b.client
        .start_download(b.now, HEARTBEAT, 1000u16.to_le_bytes())
        .unwrap();
    // ccs 1, n 2, e 1, s 1; 0x03E8 little-endian.
    expect(b.sent(), &["2B 17 10 00 E8 03 00 00"]);
    b.server("60 17 10 00 00 00 00 00");
    assert_eq!(b.sent(), Vec::<String>::new());
    assert_downloaded(b.outcome());
}

#[test]
fn expedited_download_of_one_three_and_four_bytes() {
    for (data, golden) in [
        (vec![0x05], "2F 00 20 01 05 00 00 00"),
        (vec![1, 2, 3], "27 00 20 01 01 02 03 00"),
        (vec![1, 2, 3, 4], "23 00 20 01 01 02 03 04"),
    ] {
        // Block transfer on and a threshold of 0: what fits an expedited frame stays expedited.
        let mut b = Bench::new(ClientConfig {
            block_threshold: 0,
            ..ClientConfig::default()
        });
        b.client.start_download(b.now, DOMAIN, data).unwrap();
        expect(b.sent(), &[golden]);
        b.server("60 00 20 01 00 00 00 00");
        assert_downloaded(b.outcome());
    }
}

#[test]
fn expedited_upload() {
    let mux = Address::new(0x1018, 1);
    let mut b = Bench::segmented();
    b.client.start_upload(b.now, mux).unwrap();
    expect(b.sent(), &["40 18 10 01 00 00 00 00"]);
    // scs 2, n 0, e 1, s 1: four bytes.
    b.server("43 18 10 01 78 56 34 12");
    assert!(b.sent().is_empty());
    assert_uploaded(b.outcome(), &[0x78, 0x56, 0x34, 0x12]);
}

#[test]
fn expedited_upload_without_size_takes_four_bytes() {
    let mut b = Bench::segmented();
    b.client.start_upload(b.now, HEARTBEAT).unwrap();
    b.sent();
    // e 1, s 0: the size is not indicated.
    b.server("42 17 10 00 E8 03 00 00");
    assert_uploaded(b.outcome(), &[0xE8, 0x03, 0, 0]);
}

#[test]
fn fixed_size_uploads_skip_block_mode() {
    let mut b = Bench::new(ClientConfig::default());
    b.client
        .start_upload_expecting(b.now, HEARTBEAT, 2)
        .unwrap();
    expect(b.sent(), &["40 17 10 00 00 00 00 00"]);
    // ccs 2, n 2, e 1, s 1.
    b.server("4B 17 10 00 E8 03 00 00");
    assert_uploaded(b.outcome(), &[0xE8, 0x03]);

    b.client
        .start_upload_expecting(b.now, HEARTBEAT, 8)
        .unwrap();
    expect(b.sent(), &["A4 17 10 00 7F 00 00 00"]);
}

// ---- Segmented -------------------------------------------------------------------------------

#[test]
fn segmented_download() {
    let mux = Address::new(0x1008, 0);
    let mut b = Bench::segmented();
    b.client.start_download(b.now, mux, *b"ABCDEFGHIJ").unwrap();
    // ccs 1, e 0, s 1; size 10.
    expect(b.sent(), &["21 08 10 00 0A 00 00 00"]);
    b.server("60 08 10 00 00 00 00 00");
    // Toggle 0, n 0, c 0: seven bytes.
    expect(b.sent(), &["00 41 42 43 44 45 46 47"]);
    b.server("20 00 00 00 00 00 00 00");
    // Toggle 1, n 4, c 1: 0x10 | 4 << 1 | 1.
    expect(b.sent(), &["19 48 49 4A 00 00 00 00"]);
    b.server("30 00 00 00 00 00 00 00");
    assert!(b.sent().is_empty());
    let events = b.events();
    assert_eq!(progress(&events), [(10, Some(10))], "merged reports");
    assert!(matches!(events.last(), Some(ClientEvent::Downloaded)));
    assert!(!b.client.is_busy());
}

#[test]
fn segmented_download_reports_each_confirmed_segment() {
    let mut b = Bench::segmented();
    b.client.start_download(b.now, DOMAIN, twenty()).unwrap();
    b.sent();
    b.server("60 00 20 01 00 00 00 00");
    b.sent();
    let mut seen = Vec::new();
    for response in ["20", "30", "20"] {
        b.server(&format!("{response} 00 00 00 00 00 00 00"));
        b.sent();
        seen.extend(progress(&b.events()));
    }
    assert_eq!(
        seen,
        [(7, Some(20)), (14, Some(20)), (20, Some(20))],
        "one report per response"
    );
    assert!(!b.client.is_busy());
}

#[test]
fn empty_download_is_one_empty_last_segment() {
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_download(b.now, DOMAIN, Vec::new()).unwrap();
    expect(b.sent(), &["21 00 20 01 00 00 00 00"]);
    b.server("60 00 20 01 00 00 00 00");
    // Toggle 0, n 7, c 1.
    expect(b.sent(), &["0F 00 00 00 00 00 00 00"]);
    b.server("20 00 00 00 00 00 00 00");
    assert_downloaded(b.outcome());
}

#[test]
fn segmented_upload() {
    let mux = Address::new(0x1008, 0);
    let mut b = Bench::segmented();
    b.client.start_upload(b.now, mux).unwrap();
    expect(b.sent(), &["40 08 10 00 00 00 00 00"]);
    // scs 2, e 0, s 1: size 10.
    b.server("41 08 10 00 0A 00 00 00");
    expect(b.sent(), &["60 00 00 00 00 00 00 00"]);
    b.server("00 41 42 43 44 45 46 47");
    expect(b.sent(), &["70 00 00 00 00 00 00 00"]);
    // Toggle 1, n 4, c 1.
    b.server("19 48 49 4A 00 00 00 00");
    assert!(b.sent().is_empty());
    assert_uploaded(b.outcome(), b"ABCDEFGHIJ");
}

#[test]
fn segmented_upload_toggle_error_is_aborted_on_the_wire() {
    let mux = Address::new(0x1008, 0);
    let mut b = Bench::segmented();
    b.client.start_upload(b.now, mux).unwrap();
    b.sent();
    b.server("41 08 10 00 0A 00 00 00");
    expect(b.sent(), &["60 00 00 00 00 00 00 00"]);
    // The first segment must carry toggle 0; this one carries 1.
    b.server("10 41 42 43 44 45 46 47");
    expect(b.sent(), &["80 08 10 00 00 00 03 05"]);
    assert_aborted(b.outcome(), mux, AbortCode::ToggleBit, false);
}

#[test]
fn segmented_download_toggle_error_is_aborted_on_the_wire() {
    let mut b = Bench::segmented();
    b.client.start_download(b.now, DOMAIN, twenty()).unwrap();
    b.sent();
    b.server("60 00 20 01 00 00 00 00");
    b.sent();
    // The response to the toggle-0 segment echoes toggle 1.
    b.server("30 00 00 00 00 00 00 00");
    expect(b.sent(), &["80 00 20 01 00 00 03 05"]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::ToggleBit, false);
}

#[test]
fn segmented_upload_longer_or_shorter_than_announced() {
    // Announced 3 bytes, sent 7: 0x06070012 (length too high).
    let mut b = Bench::segmented();
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("41 00 20 01 03 00 00 00");
    b.sent();
    b.server("00 01 02 03 04 05 06 07");
    expect(b.sent(), &["80 00 20 01 12 00 07 06"]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::LengthTooHigh, false);

    // Announced 10 bytes, the last segment after 7: 0x06070013 (length too low).
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("41 00 20 01 0A 00 00 00");
    b.sent();
    b.server("01 01 02 03 04 05 06 07");
    expect(b.sent(), &["80 00 20 01 13 00 07 06"]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::LengthTooLow, false);
}

// ---- Block download --------------------------------------------------------------------------

#[test]
fn block_download_of_20_bytes_with_crc() {
    let data = twenty();
    let (lo, hi) = crc_bytes(&data);
    let mut b = Bench::new(ClientConfig::default());
    b.client
        .start_download(b.now, DOMAIN, data.clone())
        .unwrap();
    // ccs 6, cc 1, s 1, cs 0; size 20.
    expect(b.sent(), &["C6 00 20 01 14 00 00 00"]);
    // scs 5, sc 1, ss 0; blksize 127.
    b.server("A4 00 20 01 7F 00 00 00");
    assert_eq!(
        b.sent(),
        [
            seg(0x01, &data[0..7]),
            seg(0x02, &data[7..14]),
            seg(0x83, &data[14..20]),
        ]
    );
    b.server("A2 03 7F 00 00 00 00 00");
    // ccs 6, n 1 (the last segment holds 6 bytes), cs 1: 0xC0 | 1 << 2 | 1; CRC little-endian.
    assert_eq!(b.sent(), [hex(&[0xC5, lo, hi, 0, 0, 0, 0, 0])]);
    b.server("A1 00 00 00 00 00 00 00");
    let events = b.events();
    assert_eq!(progress(&events), [(20, Some(20))]);
    assert!(matches!(events.last(), Some(ClientEvent::Downloaded)));
    assert!(!b.client.is_busy());
}

#[test]
fn block_download_crc_of_a_known_value() {
    // CRC-16/XMODEM of "123456789" is 0x31C3: the end frame carries C3 31.
    let mut b = Bench::new(ClientConfig::default());
    b.client
        .start_download(b.now, DOMAIN, *b"123456789")
        .unwrap();
    expect(b.sent(), &["C6 00 20 01 09 00 00 00"]);
    b.server("A4 00 20 01 7F 00 00 00");
    expect(
        b.sent(),
        &["01 31 32 33 34 35 36 37", "82 38 39 00 00 00 00 00"],
    );
    b.server("A2 02 7F 00 00 00 00 00");
    // n 5: 0xC0 | 5 << 2 | 1.
    expect(b.sent(), &["D5 C3 31 00 00 00 00 00"]);
    b.server("A1 00 00 00 00 00 00 00");
    assert_downloaded(b.outcome());
}

#[test]
fn block_download_without_crc_when_the_server_has_none() {
    let data = twenty();
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_download(b.now, DOMAIN, data).unwrap();
    b.sent();
    // sc 0.
    b.server("A0 00 20 01 7F 00 00 00");
    assert_eq!(b.sent().len(), 3);
    b.server("A2 03 7F 00 00 00 00 00");
    expect(b.sent(), &["C5 00 00 00 00 00 00 00"]);
    b.server("A1 00 00 00 00 00 00 00");
    assert_downloaded(b.outcome());
}

#[test]
fn block_download_without_crc_when_the_client_offers_none() {
    let mut b = Bench::new(ClientConfig {
        crc: false,
        ..ClientConfig::default()
    });
    b.client.start_download(b.now, DOMAIN, twenty()).unwrap();
    // cc 0: 0xC2.
    expect(b.sent(), &["C2 00 20 01 14 00 00 00"]);
    b.server("A4 00 20 01 7F 00 00 00");
    b.sent();
    b.server("A2 03 7F 00 00 00 00 00");
    expect(b.sent(), &["C5 00 00 00 00 00 00 00"]);
}

#[test]
fn block_download_resends_after_a_short_ack() {
    let data = twenty();
    let (lo, hi) = crc_bytes(&data);
    let mut b = Bench::new(ClientConfig::default());
    b.client
        .start_download(b.now, DOMAIN, data.clone())
        .unwrap();
    b.sent();
    b.server("A4 00 20 01 7F 00 00 00");
    assert_eq!(b.sent().len(), 3);
    // Only segment 1 arrived in order: the rest again, numbered from 1.
    b.server("A2 01 7F 00 00 00 00 00");
    assert_eq!(
        b.sent(),
        [seg(0x01, &data[7..14]), seg(0x82, &data[14..20])]
    );
    assert_eq!(progress(&b.events()), [(7, Some(20))]);
    // Nothing arrived: the same segments again.
    b.server("A2 00 7F 00 00 00 00 00");
    assert_eq!(
        b.sent(),
        [seg(0x01, &data[7..14]), seg(0x82, &data[14..20])]
    );
    b.server("A2 02 7F 00 00 00 00 00");
    assert_eq!(b.sent(), [hex(&[0xC5, lo, hi, 0, 0, 0, 0, 0])]);
    b.server("A1 00 00 00 00 00 00 00");
    assert_downloaded(b.outcome());
}

#[test]
fn block_download_follows_the_servers_block_size() {
    let data: Vec<u8> = (0..30).collect();
    let (lo, hi) = crc_bytes(&data);
    let mut b = Bench::new(ClientConfig::default());
    b.client
        .start_download(b.now, DOMAIN, data.clone())
        .unwrap();
    expect(b.sent(), &["C6 00 20 01 1E 00 00 00"]);
    // blksize 2.
    b.server("A4 00 20 01 02 00 00 00");
    assert_eq!(b.sent(), [seg(0x01, &data[0..7]), seg(0x02, &data[7..14])]);
    // Both arrived; next block size 1.
    b.server("A2 02 01 00 00 00 00 00");
    assert_eq!(b.sent(), [seg(0x01, &data[14..21])]);
    // Block size 3 again: the last 9 bytes in two segments, the second holding 2 (n 5).
    b.server("A2 01 03 00 00 00 00 00");
    assert_eq!(
        b.sent(),
        [seg(0x01, &data[21..28]), seg(0x82, &data[28..30])]
    );
    b.server("A2 02 03 00 00 00 00 00");
    assert_eq!(b.sent(), [hex(&[0xD5, lo, hi, 0, 0, 0, 0, 0])]);
}

#[test]
fn block_download_shrinking_block_size_during_a_resend() {
    let data: Vec<u8> = (0..35).collect();
    let mut b = Bench::new(ClientConfig::default());
    b.client
        .start_download(b.now, DOMAIN, data.clone())
        .unwrap();
    b.sent();
    b.server("A4 00 20 01 7F 00 00 00");
    assert_eq!(b.sent().len(), 5);
    // Two arrived; the server now takes one segment per block.
    b.server("A2 02 01 00 00 00 00 00");
    assert_eq!(b.sent(), [seg(0x01, &data[14..21])]);
    b.server("A2 01 01 00 00 00 00 00");
    assert_eq!(b.sent(), [seg(0x01, &data[21..28])]);
    b.server("A2 01 01 00 00 00 00 00");
    // The last segment is full: n 0.
    assert_eq!(b.sent(), [seg(0x81, &data[28..35])]);
    b.server("A2 01 01 00 00 00 00 00");
    let (lo, hi) = crc_bytes(&data);
    assert_eq!(b.sent(), [hex(&[0xC1, lo, hi, 0, 0, 0, 0, 0])]);
}

#[test]
fn block_download_of_several_full_blocks() {
    // 127 · 7 + 3 bytes: one full sub-block, then one segment of 3 bytes.
    let data: Vec<u8> = (0..127 * 7 + 3).map(|i| (i * 7 % 251) as u8).collect();
    let (lo, hi) = crc_bytes(&data);
    let mut b = Bench::new(ClientConfig::default());
    b.client
        .start_download(b.now, DOMAIN, data.clone())
        .unwrap();
    expect(b.sent(), &["C6 00 20 01 7C 03 00 00"]);
    b.server("A4 00 20 01 7F 00 00 00");
    let first = b.sent();
    assert_eq!(first.len(), 127);
    assert_eq!(first[0], seg(0x01, &data[0..7]));
    assert_eq!(first[126], seg(0x7F, &data[882..889]));
    b.server("A2 7F 7F 00 00 00 00 00");
    assert_eq!(b.sent(), [seg(0x81, &data[889..892])]);
    b.server("A2 01 7F 00 00 00 00 00");
    // n 4: 0xC0 | 4 << 2 | 1.
    assert_eq!(b.sent(), [hex(&[0xD1, lo, hi, 0, 0, 0, 0, 0])]);
}

#[test]
fn block_download_errors_in_acks() {
    // An ack of more segments than were sent: 0x05040003.
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_download(b.now, DOMAIN, twenty()).unwrap();
    b.sent();
    b.server("A4 00 20 01 7F 00 00 00");
    b.sent();
    b.server("A2 04 7F 00 00 00 00 00");
    expect(b.sent(), &["80 00 20 01 03 00 04 05"]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::InvalidSequence, false);

    // A block size of 0 or beyond 127: 0x05040002.
    for answer in ["A4 00 20 01 00 00 00 00", "A4 00 20 01 80 00 00 00"] {
        b.client.start_download(b.now, DOMAIN, twenty()).unwrap();
        b.sent();
        b.server(answer);
        expect(b.sent(), &["80 00 20 01 02 00 04 05"]);
        assert_aborted(b.outcome(), DOMAIN, AbortCode::InvalidBlockSize, false);
    }
}

#[test]
fn an_ack_drops_the_segments_of_the_sub_block_not_yet_sent() {
    let data = twenty();
    let (lo, hi) = crc_bytes(&data);
    let mut b = Bench::new(ClientConfig::default());
    b.client
        .start_download(b.now, DOMAIN, data.clone())
        .unwrap();
    b.sent();
    b.server("A4 00 20 01 7F 00 00 00");
    // Only the first segment is out when the server acknowledges it: the next sub-block starts at
    // byte 7, numbered from 1, and segments 2 and 3 of the old one are not sent any more.
    let first = b.client.poll_transmit().map(|f| hex(&f));
    assert_eq!(first, Some(seg(0x01, &data[0..7])));
    b.server("A2 01 7F 00 00 00 00 00");
    assert_eq!(
        b.sent(),
        [seg(0x01, &data[7..14]), seg(0x82, &data[14..20])]
    );
    // The same with the sub-block that holds the last segment: an ack of both while one is still
    // queued ends the download, and the end frame is all that is sent.
    b.server("A2 00 7F 00 00 00 00 00");
    let first = b.client.poll_transmit().map(|f| hex(&f));
    assert_eq!(first, Some(seg(0x01, &data[7..14])));
    b.server("A2 02 7F 00 00 00 00 00");
    assert_eq!(b.sent(), [hex(&[0xC5, lo, hi, 0, 0, 0, 0, 0])]);
    b.server("A1 00 00 00 00 00 00 00");
    assert_downloaded(b.outcome());
}

#[test]
fn an_abort_with_its_unused_bits_set_is_an_abort() {
    // CiA 301 §7.2.4.3.17: an abort is cs = 4 in bits 7–5; bits 4–0 are not used.
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_upload(b.now, DOMAIN).unwrap();
    expect(b.sent(), &["A4 00 20 01 7F 00 00 00"]);
    // To the block upload initiate: the upload again, normal.
    b.server("9F 00 20 01 01 00 04 05");
    expect(b.sent(), &["40 00 20 01 00 00 00 00"]);
    b.server("81 00 20 01 00 00 02 06");
    assert!(b.sent().is_empty());
    assert_aborted(b.outcome(), DOMAIN, AbortCode::NoObject, true);

    // After the last segment of a block upload, waiting for its end.
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("C6 00 20 01 03 00 00 00");
    expect(b.sent(), &["A3 00 00 00 00 00 00 00"]);
    b.server(&seg(0x81, &[1, 2, 3]));
    expect(b.sent(), &["A2 01 7F 00 00 00 00 00"]);
    b.server("84 00 20 01 04 00 04 05");
    assert!(b.sent().is_empty());
    assert_aborted(b.outcome(), DOMAIN, AbortCode::CrcError, true);
}

#[test]
fn an_initiate_response_for_another_entry_is_refused() {
    // The server answers for 0x2000:02 where 0x2000:01 was asked: abort 0x05040001 (command
    // specifier not valid or unknown) from the client, for each kind of initiate.
    let wrong = "80 00 20 01 01 00 04 05";
    let mut b = Bench::segmented();
    for answer in ["43 00 20 02 01 02 03 04", "41 00 20 02 05 00 00 00"] {
        b.client.start_upload(b.now, DOMAIN).unwrap();
        expect(b.sent(), &["40 00 20 01 00 00 00 00"]);
        b.server(answer);
        expect(b.sent(), &[wrong]);
        assert_aborted(b.outcome(), DOMAIN, AbortCode::InvalidCommand, false);
    }
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_download(b.now, DOMAIN, twenty()).unwrap();
    expect(b.sent(), &["C6 00 20 01 14 00 00 00"]);
    b.server("A4 00 20 02 7F 00 00 00");
    expect(b.sent(), &[wrong]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::InvalidCommand, false);
    b.client.start_upload(b.now, DOMAIN).unwrap();
    expect(b.sent(), &["A4 00 20 01 7F 00 00 00"]);
    b.server("C6 00 20 02 14 00 00 00");
    expect(b.sent(), &[wrong]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::InvalidCommand, false);
}

#[test]
fn data_lengths_and_the_streams_of_a_write_sink() {
    struct Five;
    impl DownloadSource for Five {
        fn len(&self) -> u64 {
            5
        }
        fn read(&mut self, _: &mut [u8]) -> io::Result<usize> {
            Ok(0)
        }
    }
    struct Nothing;
    impl DownloadSource for Nothing {
        fn len(&self) -> u64 {
            0
        }
        fn read(&mut self, _: &mut [u8]) -> io::Result<usize> {
            Ok(0)
        }
    }
    assert!(!Five.is_empty());
    assert!(Nothing.is_empty());
    let five = DownloadData::Stream(Box::new(Five));
    assert!(!five.is_empty());
    assert_eq!(format!("{five:?}"), "Stream(5 bytes)");
    assert!(DownloadData::from(Vec::new()).is_empty());
    let bytes = DownloadData::from(vec![1, 2]);
    assert!(!bytes.is_empty());
    assert_eq!(format!("{bytes:?}"), "Bytes([1, 2])");

    // A write sink writes each received piece and flushes once, at the end.
    #[derive(Default)]
    struct Log {
        data: Vec<u8>,
        flushes: usize,
    }
    struct Shared(Arc<Mutex<Log>>);
    impl io::Write for Shared {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            self.0.lock().unwrap().data.extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            self.0.lock().unwrap().flushes += 1;
            Ok(())
        }
    }
    let log = Arc::new(Mutex::new(Log::default()));
    let mut b = Bench::segmented();
    let sink: Box<dyn UploadSink + Send> = Box::new(WriteSink(Shared(Arc::clone(&log))));
    b.client.start_upload_to(b.now, DOMAIN, sink).unwrap();
    expect(b.sent(), &["40 00 20 01 00 00 00 00"]);
    b.server("41 00 20 01 09 00 00 00");
    b.sent();
    b.server("00 31 32 33 34 35 36 37");
    b.sent();
    assert_eq!(log.lock().unwrap().data, b"1234567");
    assert_eq!(log.lock().unwrap().flushes, 0);
    b.server("1B 38 39 00 00 00 00 00");
    assert!(matches!(b.outcome(), ClientEvent::UploadedToSink { .. }));
    assert_eq!(log.lock().unwrap().data, b"123456789");
    assert_eq!(log.lock().unwrap().flushes, 1);
}

#[test]
fn the_configuration_is_read_and_changed_between_transfers() {
    let config = ClientConfig {
        timeout: Duration::from_millis(250),
        block: false,
        block_size: 9,
        ..ClientConfig::default()
    };
    let mut b = Bench::new(config);
    assert_eq!(b.client.config().timeout, Duration::from_millis(250));
    assert!(!b.client.config().block);
    assert_eq!(b.client.config().block_size, 9);
    let shown = format!("{:?}", b.client);
    assert!(
        shown.starts_with("SdoClient { config: ClientConfig { timeout: 250ms, block: false,"),
        "{shown}"
    );
    assert!(
        shown.ends_with("busy: false, response_due: None, .. }"),
        "{shown}"
    );
    // Segmented, as configured.
    b.client.start_download(b.now, DOMAIN, twenty()).unwrap();
    expect(b.sent(), &["21 00 20 01 14 00 00 00"]);
    let shown = format!("{:?}", b.client);
    assert!(shown.contains("busy: true, response_due: Some("), "{shown}");
    assert!(b.client.abort(AbortCode::General));
    b.sent();
    b.events();
    // Block transfer and a block size of 5 from the next transfer on.
    b.client.config_mut().block = true;
    b.client.config_mut().block_size = 5;
    assert!(b.client.config().block);
    b.client.start_upload(b.now, DOMAIN).unwrap();
    expect(b.sent(), &["A4 00 20 01 05 00 00 00"]);
}

// ---- Fall-back -------------------------------------------------------------------------------

#[test]
fn block_download_refused_falls_back_to_segmented() {
    let data = twenty();
    let mut b = Bench::new(ClientConfig::default());
    b.client
        .start_download(b.now, DOMAIN, data.clone())
        .unwrap();
    expect(b.sent(), &["C6 00 20 01 14 00 00 00"]);
    // Abort 0x05040001: the server knows no block transfer.
    b.server("80 00 20 01 01 00 04 05");
    expect(b.sent(), &["21 00 20 01 14 00 00 00"]);
    assert!(b.events().is_empty(), "the fall-back is silent");
    b.server("60 00 20 01 00 00 00 00");
    assert_eq!(b.sent(), [seg(0x00, &data[0..7])]);
    b.server("20 00 00 00 00 00 00 00");
    assert_eq!(b.sent(), [seg(0x10, &data[7..14])]);
    b.server("30 00 00 00 00 00 00 00");
    // Toggle 0, n 1, c 1.
    assert_eq!(b.sent(), [seg(0x03, &data[14..20])]);
    b.server("20 00 00 00 00 00 00 00");
    assert_downloaded(b.outcome());
}

#[test]
fn fall_back_happens_once() {
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_download(b.now, DOMAIN, twenty()).unwrap();
    b.sent();
    // Any abort to a block initiate: 0x06010002 (read-only) too.
    b.server("80 00 20 01 02 00 01 06");
    expect(b.sent(), &["21 00 20 01 14 00 00 00"]);
    b.server("80 00 20 01 02 00 01 06");
    assert!(b.sent().is_empty());
    assert_aborted(b.outcome(), DOMAIN, AbortCode::ReadOnly, true);
}

#[test]
fn block_upload_refused_falls_back_to_normal_upload() {
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_upload(b.now, DOMAIN).unwrap();
    // ccs 5, cc 1, cs 0; blksize 127, pst 0.
    expect(b.sent(), &["A4 00 20 01 7F 00 00 00"]);
    b.server("80 00 20 01 01 00 04 05");
    expect(b.sent(), &["40 00 20 01 00 00 00 00"]);
    assert!(b.events().is_empty());
    b.server("41 00 20 01 09 00 00 00");
    expect(b.sent(), &["60 00 00 00 00 00 00 00"]);
    b.server("00 31 32 33 34 35 36 37");
    expect(b.sent(), &["70 00 00 00 00 00 00 00"]);
    // Toggle 1, n 5, c 1.
    b.server("1B 38 39 00 00 00 00 00");
    assert_uploaded(b.outcome(), b"123456789");
}

#[test]
fn an_abort_after_the_block_initiate_is_final() {
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_download(b.now, DOMAIN, twenty()).unwrap();
    b.sent();
    b.server("A4 00 20 01 7F 00 00 00");
    b.sent();
    b.server("80 00 20 01 04 00 04 05");
    assert!(b.sent().is_empty());
    assert_aborted(b.outcome(), DOMAIN, AbortCode::CrcError, true);
}
