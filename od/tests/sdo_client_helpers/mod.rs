//! What the SDO client tests share (`sdo_client`, `sdo_client_block_upload`, `sdo_client_streaming`):
//! frames from hexadecimal text and the checks of the client's events. Every frame the client sends is
//! asserted byte for byte against sequences written from the layouts of CiA 301 §7.2.4.3 (command byte,
//! multiplexer, data), and every server frame is written the same way.
//!
//! Command bytes used (ccs/scs in bits 7–5):
//! - client: `2B`/`23`/`2F` expedited download of 2/4/1 bytes, `21` segmented download with size,
//!   `00`/`10` + n·2 + c download segment, `40` initiate upload, `60`/`70` upload segment request,
//!   `C6` initiate block download (CRC, size), `C1` + n·4 end block download, `A4` initiate block
//!   upload (CRC), `A3` start block upload, `A2` block upload ack, `A1` end block upload response,
//!   `80` abort.
//! - server: `60` initiate download response, `20`/`30` download segment response, `43`/`4B`
//!   expedited upload of 4/2 bytes, `41` segmented upload with size, `A4`/`A0` initiate block download
//!   response with/without CRC, `A2` block download ack, `A1` end block download response, `C6`/`C2`
//!   initiate block upload response with/without CRC, `C1` + n·4 end block upload.
#![allow(dead_code)]

use std::time::{Duration, Instant};

use od::sdo::{Address, ClientConfig, ClientEvent, Crc16, Frame, SdoClient, SdoClientError};
use od::AbortCode;

/// Eight bytes from hexadecimal text (`"2B 17 10 00 E8 03 00 00"`).
pub fn frame(hex: &str) -> Frame {
    let bytes: Vec<u8> = hex
        .split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).unwrap())
        .collect();
    bytes.try_into().expect("eight bytes")
}

pub fn hex(f: &Frame) -> String {
    f.iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// A segment frame: byte 0, then `data` padded with zeros to seven bytes.
pub fn seg(byte0: u8, data: &[u8]) -> String {
    let mut f = [0u8; 8];
    f[0] = byte0;
    f[1..1 + data.len()].copy_from_slice(data);
    hex(&f)
}

/// A client on a simulated clock.
pub struct Bench {
    pub client: SdoClient,
    pub t0: Instant,
    pub now: Instant,
}

impl Bench {
    pub fn new(config: ClientConfig) -> Bench {
        let t0 = Instant::now();
        Bench {
            client: SdoClient::new(config),
            t0,
            now: t0,
        }
    }

    pub fn segmented() -> Bench {
        Bench::new(ClientConfig {
            block: false,
            ..ClientConfig::default()
        })
    }

    /// Everything the client queued, as hexadecimal text.
    pub fn sent(&mut self) -> Vec<String> {
        std::iter::from_fn(|| self.client.poll_transmit())
            .map(|f| hex(&f))
            .collect()
    }

    /// The server sends `hex`.
    pub fn server(&mut self, hex: &str) {
        self.client.handle_frame(self.now, &frame(hex));
    }

    pub fn events(&mut self) -> Vec<ClientEvent> {
        std::iter::from_fn(|| self.client.poll_event()).collect()
    }

    /// The final event, after any progress reports; asserts there is exactly one.
    pub fn outcome(&mut self) -> ClientEvent {
        let mut ends: Vec<ClientEvent> = self
            .events()
            .into_iter()
            .filter(|e| !matches!(e, ClientEvent::Progress { .. }))
            .collect();
        assert_eq!(ends.len(), 1, "{ends:?}");
        assert!(!self.client.is_busy());
        assert_eq!(self.client.poll_timeout(), None);
        ends.remove(0)
    }

    pub fn advance(&mut self, ms: u64) {
        self.now += Duration::from_millis(ms);
        self.client.handle_timeout(self.now);
    }
}

pub fn expect(sent: Vec<String>, golden: &[&str]) {
    let golden: Vec<String> = golden.iter().map(|s| hex(&frame(s))).collect();
    assert_eq!(sent, golden);
}

pub fn assert_downloaded(e: ClientEvent) {
    assert!(matches!(e, ClientEvent::Downloaded), "{e:?}");
}

pub fn assert_uploaded(e: ClientEvent, data: &[u8]) {
    match e {
        ClientEvent::Uploaded(got) => assert_eq!(got, data),
        other => panic!("{other:?}"),
    }
}

pub fn assert_aborted(e: ClientEvent, mux: Address, code: AbortCode, by_server: bool) {
    match e {
        ClientEvent::Failed(SdoClientError::Aborted {
            index,
            sub,
            code: c,
            by_server: b,
        }) => {
            assert_eq!((index, sub, c, b), (mux.index, mux.sub, code, by_server));
        }
        other => panic!("{other:?}"),
    }
}

pub fn progress(events: &[ClientEvent]) -> Vec<(u64, Option<u64>)> {
    events
        .iter()
        .filter_map(|e| match *e {
            ClientEvent::Progress { done, total } => Some((done, total)),
            _ => None,
        })
        .collect()
}

pub const HEARTBEAT: Address = Address::new(0x1017, 0);
pub const DOMAIN: Address = Address::new(0x2000, 1);

/// 20 bytes: two full segments and one of six bytes (20 = 2·7 + 6).
pub fn twenty() -> Vec<u8> {
    (1..=20).collect()
}

pub fn crc_bytes(data: &[u8]) -> (u8, u8) {
    let [lo, hi] = Crc16::of(data).to_le_bytes();
    (lo, hi)
}
