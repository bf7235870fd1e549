//! Unit tests of the client's data handling: bounded reservation, reads from short-reading sources,
//! size checks.

use std::io;

use super::data::{check_size, Sink, Source};
use super::*;

#[test]
fn announced_size_reserves_at_most_the_cap() {
    let mut sink = Sink::Memory {
        buf: Vec::new(),
        limit: usize::MAX,
    };
    assert!(sink.announce(Some(u32::MAX)).is_ok());
    match &sink {
        Sink::Memory { buf, .. } => assert!(buf.capacity() <= UPLOAD_PREALLOC_CAP * 2),
        Sink::Stream { .. } => unreachable!(),
    }
    let mut small = Sink::Memory {
        buf: Vec::new(),
        limit: 100,
    };
    assert!(small.announce(Some(100)).is_ok());
    assert_eq!(
        small.announce(Some(101)).err().map(|f| f.code),
        Some(AbortCode::OutOfMemory)
    );
}

#[test]
fn memory_sink_grows_as_data_arrives_up_to_the_limit() {
    let mut sink = Sink::Memory {
        buf: Vec::new(),
        limit: 10,
    };
    assert!(sink.push(&[1; 7]).is_ok());
    assert_eq!(sink.received(), 7);
    assert_eq!(
        sink.push(&[1; 7]).err().map(|f| f.code),
        Some(AbortCode::OutOfMemory)
    );
    assert!(sink.push(&[2; 3]).is_ok());
    match sink.finish() {
        Ok(ClientEvent::Uploaded(data)) => assert_eq!(data, [1, 1, 1, 1, 1, 1, 1, 2, 2, 2]),
        Ok(other) => panic!("{other:?}"),
        Err(f) => panic!("{:?}", f.code),
    }
}

/// A source that gives one byte per read and is sometimes interrupted.
struct Trickle {
    data: Vec<u8>,
    pos: usize,
    calls: usize,
}

impl DownloadSource for Trickle {
    fn len(&self) -> u64 {
        self.data.len() as u64
    }

    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.calls += 1;
        if self.calls.is_multiple_of(3) {
            return Err(io::ErrorKind::Interrupted.into());
        }
        if buf.is_empty() || self.pos == self.data.len() {
            return Ok(0);
        }
        buf[0] = self.data[self.pos];
        self.pos += 1;
        Ok(1)
    }
}

#[test]
fn source_reads_fill_despite_short_and_interrupted_reads() {
    let data: Vec<u8> = (0..20).collect();
    let trickle: Box<dyn DownloadSource + Send> = Box::new(Trickle {
        data: data.clone(),
        pos: 0,
        calls: 0,
    });
    let mut source = Source::new(DownloadData::Stream(trickle));
    let mut out = Vec::new();
    assert!(source.read_into(&mut out, 7).is_ok());
    assert!(
        source.read_into(&mut out, 100).is_ok(),
        "capped at what remains"
    );
    assert_eq!(out, data);
    assert_eq!(source.remaining(), 0);
    assert!(source.read_into(&mut out, 7).is_ok());
    assert_eq!(out.len(), 20);
}

#[test]
fn sizes_against_the_announcement() {
    assert!(check_size(5, Some(10), false).is_ok());
    assert!(check_size(10, Some(10), true).is_ok());
    assert!(check_size(10, None, true).is_ok());
    let code = |r: Result<(), data::Failure>| r.err().map(|f| f.code);
    assert_eq!(
        code(check_size(11, Some(10), false)),
        Some(AbortCode::LengthTooHigh)
    );
    assert_eq!(
        code(check_size(9, Some(10), true)),
        Some(AbortCode::LengthTooLow)
    );
}

#[test]
fn block_size_0_in_the_config_counts_as_1() {
    let mut client = SdoClient::new(ClientConfig {
        block_size: 0,
        ..ClientConfig::default()
    });
    let now = std::time::Instant::now();
    assert!(client.start_upload(now, Address::new(0x2000, 0)).is_ok());
    assert_eq!(
        client.poll_transmit(),
        Some([0xA4, 0x00, 0x20, 0x00, 1, 0, 0, 0])
    );
}

#[test]
fn the_response_timer_follows_the_config() {
    let mut client = SdoClient::new(ClientConfig {
        timeout: Duration::from_millis(250),
        ..ClientConfig::default()
    });
    let now = std::time::Instant::now();
    assert_eq!(client.poll_timeout(), None);
    assert!(client.start_upload(now, Address::new(0x1000, 0)).is_ok());
    assert_eq!(
        client.poll_timeout(),
        Some(now + Duration::from_millis(250))
    );
    client.reset();
    assert_eq!(client.poll_timeout(), None);
    assert_eq!(client.poll_transmit(), None);
    assert!(!client.is_busy());
}

#[test]
fn errors_name_the_entry_the_side_and_the_code() {
    let e = SdoClientError::Aborted {
        index: 0x1017,
        sub: 0,
        code: AbortCode::ReadOnly,
        by_server: true,
    };
    assert_eq!(
        e.to_string(),
        "SDO transfer of 0x1017:00 aborted by the server: 0x06010002 (Attempt to write a read only object)"
    );
    let e = SdoClientError::Aborted {
        index: 0x2000,
        sub: 1,
        code: AbortCode::Timeout,
        by_server: false,
    };
    assert_eq!(
        e.to_string(),
        "SDO transfer of 0x2000:01 aborted by the client: 0x05040000 (SDO protocol timed out)"
    );
}
