//! The SDO client against scripted server frames: memory bounds, streaming sources and sinks, and
//! robustness against arbitrary frames. The frames are written from the layouts of CiA 301 §7.2.4.3;
//! `sdo_client_helpers` lists the command bytes used.

mod sdo_client_helpers;

use od::sdo::client::ReadSource;
use od::sdo::{
    ClientConfig, ClientEvent, DownloadData, DownloadSource, SdoClientError, UploadSink,
};
use od::AbortCode;
use sdo_client_helpers::*;
use std::io;
use std::sync::{Arc, Mutex};

// ---- Memory bounds ---------------------------------------------------------------------------

#[test]
fn upload_over_the_limit_is_refused() {
    let config = ClientConfig {
        upload_limit: 8,
        block: false,
        ..ClientConfig::default()
    };
    // Announced beyond the limit: aborted before any segment is asked for.
    let mut b = Bench::new(config.clone());
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("41 00 20 01 09 00 00 00");
    expect(b.sent(), &["80 00 20 01 05 00 04 05"]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::OutOfMemory, false);

    // Not announced, and more data than the limit.
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("40 00 20 01 00 00 00 00");
    expect(b.sent(), &["60 00 00 00 00 00 00 00"]);
    b.server("00 01 02 03 04 05 06 07");
    expect(b.sent(), &["70 00 00 00 00 00 00 00"]);
    b.server("10 01 02 03 04 05 06 07");
    expect(b.sent(), &["80 00 20 01 05 00 04 05"]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::OutOfMemory, false);

    // A block upload announcing 4 GiB − 1 bytes.
    let mut b = Bench::new(ClientConfig::default());
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("C6 00 20 01 FF FF FF FF");
    expect(b.sent(), &["80 00 20 01 05 00 04 05"]);
    assert_aborted(b.outcome(), DOMAIN, AbortCode::OutOfMemory, false);
}

#[test]
fn a_large_announcement_within_the_limit_is_accepted() {
    // 16 MiB − 1 announced: accepted, and the client asks for the first segment (how much it reserves
    // ahead is checked by the client's unit tests).
    let mut b = Bench::segmented();
    b.client.start_upload(b.now, DOMAIN).unwrap();
    b.sent();
    b.server("41 00 20 01 FF FF FF 00");
    expect(b.sent(), &["60 00 00 00 00 00 00 00"]);
    assert!(b.client.is_busy());
}

#[test]
fn downloads_beyond_4_gib_are_refused() {
    struct Huge;
    impl DownloadSource for Huge {
        fn len(&self) -> u64 {
            1 << 32
        }
        fn read(&mut self, _: &mut [u8]) -> io::Result<usize> {
            Ok(0)
        }
    }
    let mut b = Bench::new(ClientConfig::default());
    let source: Box<dyn DownloadSource + Send> = Box::new(Huge);
    assert!(matches!(
        b.client.start_download(b.now, DOMAIN, source),
        Err(SdoClientError::TooLarge { len: 0x1_0000_0000 })
    ));
    assert!(!b.client.is_busy());
    assert!(b.sent().is_empty());

    // 4 GiB − 1 is the most an initiate's size field holds: taken.
    struct Largest;
    impl DownloadSource for Largest {
        fn len(&self) -> u64 {
            u64::from(u32::MAX)
        }
        fn read(&mut self, _: &mut [u8]) -> io::Result<usize> {
            Ok(0)
        }
    }
    let source: Box<dyn DownloadSource + Send> = Box::new(Largest);
    b.client.start_download(b.now, DOMAIN, source).unwrap();
    expect(b.sent(), &["C6 00 20 01 FF FF FF FF"]);
}

// ---- Streaming -------------------------------------------------------------------------------

#[test]
fn block_download_from_a_streaming_source() {
    let data: Vec<u8> = (0..200).map(|i| i as u8).collect();
    let (lo, hi) = crc_bytes(&data);
    let mut b = Bench::new(ClientConfig::default());
    let source = ReadSource::new(io::Cursor::new(data.clone()), 200);
    b.client
        .start_download(b.now, DOMAIN, DownloadData::Stream(Box::new(source)))
        .unwrap();
    expect(b.sent(), &["C6 00 20 01 C8 00 00 00"]);
    b.server("A4 00 20 01 7F 00 00 00");
    let segs = b.sent();
    // 200 = 28 · 7 + 4.
    assert_eq!(segs.len(), 29);
    assert_eq!(segs[28], seg(0x80 | 29, &data[196..200]));
    b.server("A2 1D 7F 00 00 00 00 00");
    // n 3: 0xC0 | 3 << 2 | 1.
    assert_eq!(b.sent(), [hex(&[0xCD, lo, hi, 0, 0, 0, 0, 0])]);
    b.server("A1 00 00 00 00 00 00 00");
    assert_downloaded(b.outcome());
}

#[test]
fn a_source_that_ends_early_aborts_the_transfer() {
    let mut b = Bench::segmented();
    // Announces 20 bytes, holds 10.
    let source = ReadSource::new(io::Cursor::new(vec![7u8; 10]), 20);
    b.client
        .start_download(b.now, DOMAIN, DownloadData::Stream(Box::new(source)))
        .unwrap();
    expect(b.sent(), &["21 00 20 01 14 00 00 00"]);
    b.server("60 00 20 01 00 00 00 00");
    b.sent();
    b.server("20 00 00 00 00 00 00 00");
    // 0x08000000: general error.
    expect(b.sent(), &["80 00 20 01 00 00 00 08"]);
    match b.outcome() {
        ClientEvent::Failed(SdoClientError::Io(e)) => {
            assert_eq!(e.kind(), io::ErrorKind::UnexpectedEof)
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_failing_expedited_source_fails_the_start() {
    struct Broken;
    impl DownloadSource for Broken {
        fn len(&self) -> u64 {
            2
        }
        fn read(&mut self, _: &mut [u8]) -> io::Result<usize> {
            Err(io::Error::other("disk gone"))
        }
    }
    let mut b = Bench::new(ClientConfig::default());
    let source: Box<dyn DownloadSource + Send> = Box::new(Broken);
    assert!(matches!(
        b.client.start_download(b.now, DOMAIN, source),
        Err(SdoClientError::Io(_))
    ));
    assert!(!b.client.is_busy());
    assert!(b.sent().is_empty());
}

/// A sink that keeps what it gets where the test can see it.
#[derive(Clone, Default)]
struct Shared {
    data: Arc<Mutex<Vec<u8>>>,
    finished: Arc<Mutex<bool>>,
    fail: bool,
}

impl UploadSink for Shared {
    fn write_data(&mut self, data: &[u8]) -> io::Result<()> {
        if self.fail {
            return Err(io::Error::other("full"));
        }
        self.data.lock().unwrap().extend_from_slice(data);
        Ok(())
    }

    fn finish(&mut self) -> io::Result<()> {
        *self.finished.lock().unwrap() = true;
        Ok(())
    }
}

#[test]
fn block_upload_into_a_sink() {
    let data = twenty();
    let (lo, hi) = crc_bytes(&data);
    let sink = Shared::default();
    let mut b = Bench::new(ClientConfig {
        upload_limit: 4,
        ..ClientConfig::default()
    });
    b.client
        .start_upload_to(b.now, DOMAIN, Box::new(sink.clone()))
        .unwrap();
    b.sent();
    b.server("C6 00 20 01 14 00 00 00");
    b.sent();
    b.server(&seg(0x01, &data[0..7]));
    assert_eq!(
        *sink.data.lock().unwrap(),
        data[0..7],
        "in-order data goes at once"
    );
    b.server(&seg(0x02, &data[7..14]));
    b.server(&seg(0x83, &data[14..20]));
    b.sent();
    assert_eq!(
        sink.data.lock().unwrap().len(),
        14,
        "the last segment waits for n"
    );
    b.server(&hex(&[0xC5, lo, hi, 0, 0, 0, 0, 0]));
    expect(b.sent(), &["A1 00 00 00 00 00 00 00"]);
    assert!(matches!(
        b.outcome(),
        ClientEvent::UploadedToSink { len: 20 }
    ));
    assert_eq!(
        *sink.data.lock().unwrap(),
        data,
        "no memory limit for sinks"
    );
    assert!(*sink.finished.lock().unwrap());
}

#[test]
fn a_failing_sink_aborts_the_upload() {
    let sink = Shared {
        fail: true,
        ..Shared::default()
    };
    let mut b = Bench::segmented();
    b.client
        .start_upload_to(b.now, DOMAIN, Box::new(sink.clone()))
        .unwrap();
    b.sent();
    b.server("41 00 20 01 09 00 00 00");
    b.sent();
    b.server("00 31 32 33 34 35 36 37");
    // 0x08000020: data cannot be transferred or stored to the application.
    expect(b.sent(), &["80 00 20 01 20 00 00 08"]);
    assert!(matches!(
        b.outcome(),
        ClientEvent::Failed(SdoClientError::Io(_))
    ));
    assert!(!*sink.finished.lock().unwrap());
}

// ---- Robustness ------------------------------------------------------------------------------

mod arbitrary_frames {
    use super::*;
    use proptest::prelude::*;

    /// Starts one kind of transfer and brings it into a state where it waits for frames.
    fn start(kind: u8, b: &mut Bench) {
        let big: Vec<u8> = (0..300).map(|i| i as u8).collect();
        match kind % 6 {
            0 => b.client.start_download(b.now, DOMAIN, [1, 2]).unwrap(),
            1 => b.client.start_download(b.now, DOMAIN, big).unwrap(),
            2 => {
                b.client.start_download(b.now, DOMAIN, big).unwrap();
                b.server("A4 00 20 01 7F 00 00 00");
            }
            3 => b.client.start_upload(b.now, DOMAIN).unwrap(),
            4 => {
                b.client.start_upload(b.now, DOMAIN).unwrap();
                b.server("C6 00 20 01 00 01 00 00");
            }
            _ => {
                b.config_segmented();
                b.client.start_upload(b.now, DOMAIN).unwrap();
                b.server("41 00 20 01 00 01 00 00");
            }
        }
    }

    impl Bench {
        fn config_segmented(&mut self) {
            self.client.config_mut().block = false;
        }
    }

    proptest! {
        #[test]
        fn no_frame_makes_the_client_panic_or_queue_without_bound(
            kind in 0u8..6,
            frames in proptest::collection::vec(proptest::array::uniform8(any::<u8>()), 0..64),
            steps in proptest::collection::vec(0u64..400, 0..8),
        ) {
            let mut b = Bench::new(ClientConfig { upload_limit: 1024, ..ClientConfig::default() });
            start(kind, &mut b);
            let mut ends = 0;
            for (i, f) in frames.iter().enumerate() {
                b.client.handle_frame(b.now, f);
                let sent = b.sent();
                prop_assert!(sent.len() <= 128);
                if let Some(&ms) = steps.get(i % steps.len().max(1)) {
                    b.advance(ms);
                    prop_assert!(b.sent().len() <= 1);
                }
                ends += b
                    .events()
                    .iter()
                    .filter(|e| !matches!(e, ClientEvent::Progress { .. }))
                    .count();
            }
            prop_assert!(ends <= 1);
            prop_assert_eq!(b.client.is_busy(), ends == 0);
        }
    }
}
