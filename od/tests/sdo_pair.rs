//! Client and server driven together through a simulated CAN channel and clock: every transfer mode end
//! to end, aborts and timeouts, and a property test through a channel that drops, duplicates and
//! reorders frames.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use od::sdo::client::{ClientConfig, ClientEvent, SdoClient, SdoClientError};
use od::sdo::server::{SdoServer, ServerConfig};
use od::sdo::{Address, Frame};
use od::{AbortCode, AccessType, DataType, Dictionary, Object, SubObject, Value};
use proptest::prelude::*;

const DOMAIN: Address = Address::new(0x2000, 0);
const HEARTBEAT: Address = Address::new(0x1017, 0);

fn dictionary() -> Dictionary {
    let mut d = Dictionary::new();
    d.insert(Object::var(
        0x1017,
        SubObject::new(
            "Producer heartbeat time",
            DataType::Unsigned16,
            AccessType::Rw,
        ),
    ));
    d.insert(Object::var(
        0x2000,
        SubObject::new("Blob", DataType::Domain, AccessType::Rw),
    ));
    d.insert(Object::var(
        0x1000,
        SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro)
            .with_default(Value::Uint(0x0002_0192)),
    ));
    d
}

/// What the channel does to frames, decided by a seeded generator.
#[derive(Debug, Clone, Copy, Default)]
struct Faults {
    /// Per mille of frames dropped.
    drop: u16,
    /// Per mille of frames sent twice.
    duplicate: u16,
    /// Per mille of frames delayed behind the next one.
    reorder: u16,
    seed: u64,
}

struct Rng(u64);

impl Rng {
    fn per_mille(&mut self, p: u16) -> bool {
        // xorshift64*
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 33) % 1000 < p as u64
    }
}

/// A client, a server and its dictionary, and the two directions of a simulated channel.
struct Pair {
    client: SdoClient,
    server: SdoServer,
    dict: Dictionary,
    now: Instant,
    latency: Duration,
    to_server: VecDeque<(Instant, Frame)>,
    to_client: VecDeque<(Instant, Frame)>,
    faults: Faults,
    rng: Rng,
    frames: u64,
}

impl Pair {
    fn new(client: ClientConfig, server: ServerConfig, faults: Faults) -> Pair {
        Pair {
            client: SdoClient::new(client),
            server: SdoServer::new(server),
            dict: dictionary(),
            now: Instant::now(),
            latency: Duration::from_micros(200),
            to_server: VecDeque::new(),
            to_client: VecDeque::new(),
            faults,
            rng: Rng(faults.seed | 1),
            frames: 0,
        }
    }

    fn send(
        queue: &mut VecDeque<(Instant, Frame)>,
        rng: &mut Rng,
        faults: Faults,
        at: Instant,
        f: Frame,
    ) {
        if rng.per_mille(faults.drop) {
            return;
        }
        let copies = if rng.per_mille(faults.duplicate) {
            2
        } else {
            1
        };
        for _ in 0..copies {
            if rng.per_mille(faults.reorder) && !queue.is_empty() {
                let i = queue.len() - 1;
                queue.insert(i, (at, f));
            } else {
                queue.push_back((at, f));
            }
        }
    }

    /// Moves frames and time until the client reports the end of its transfer (or `limit` steps pass).
    fn drive(&mut self) -> Result<Option<Vec<u8>>, SdoClientError> {
        for _ in 0..2_000_000 {
            while let Some(f) = self.client.poll_transmit() {
                self.frames += 1;
                Pair::send(
                    &mut self.to_server,
                    &mut self.rng,
                    self.faults,
                    self.now + self.latency,
                    f,
                );
            }
            while let Some(f) = self.server.poll_transmit() {
                self.frames += 1;
                Pair::send(
                    &mut self.to_client,
                    &mut self.rng,
                    self.faults,
                    self.now + self.latency,
                    f,
                );
            }
            while self.server.poll_event().is_some() {}
            while let Some(e) = self.client.poll_event() {
                match e {
                    ClientEvent::Progress { .. } => {}
                    ClientEvent::Downloaded => return Ok(None),
                    ClientEvent::Uploaded(bytes) => return Ok(Some(bytes)),
                    ClientEvent::UploadedToSink { .. } => return Ok(None),
                    ClientEvent::Failed(e) => return Err(e),
                    other => panic!("an event this test does not know: {other:?}"),
                }
            }
            // The next thing that happens: a frame arrives or a timer fires.
            let next = [
                self.to_server.front().map(|f| f.0),
                self.to_client.front().map(|f| f.0),
                self.client.poll_timeout(),
                self.server.poll_timeout(),
            ]
            .into_iter()
            .flatten()
            .min();
            let Some(next) = next else {
                panic!("nothing left to happen and the client has not finished")
            };
            self.now = self.now.max(next);
            if let Some(&(t, f)) = self.to_server.front() {
                if t <= self.now {
                    self.to_server.pop_front();
                    self.server.handle_frame(self.now, &f, &mut self.dict);
                    continue;
                }
            }
            if let Some(&(t, f)) = self.to_client.front() {
                if t <= self.now {
                    self.to_client.pop_front();
                    self.client.handle_frame(self.now, &f);
                    continue;
                }
            }
            if self.server.poll_timeout().is_some_and(|t| t <= self.now) {
                self.server.handle_timeout(self.now);
            }
            if self.client.poll_timeout().is_some_and(|t| t <= self.now) {
                self.client.handle_timeout(self.now);
            }
        }
        panic!("the transfer did not end");
    }

    fn download(&mut self, mux: Address, data: &[u8]) -> Result<(), SdoClientError> {
        self.client.start_download(self.now, mux, data.to_vec())?;
        self.drive().map(|_| ())
    }

    fn upload(&mut self, mux: Address) -> Result<Vec<u8>, SdoClientError> {
        self.client.start_upload(self.now, mux)?;
        self.drive().map(|b| b.unwrap_or_default())
    }

    /// Lets both sides' timers run out, so that a half-finished transfer ends on the server too.
    fn settle(&mut self) {
        self.now += Duration::from_secs(5);
        self.to_client.clear();
        self.to_server.clear();
        if self.server.poll_timeout().is_some_and(|t| t <= self.now) {
            self.server.handle_timeout(self.now);
        }
        while self.server.poll_transmit().is_some() {}
        while self.server.poll_event().is_some() {}
    }
}

fn modes() -> [(ClientConfig, &'static str); 3] {
    [
        (
            ClientConfig {
                block: false,
                ..ClientConfig::default()
            },
            "segmented",
        ),
        (ClientConfig::default(), "block with CRC"),
        (
            ClientConfig {
                crc: false,
                ..ClientConfig::default()
            },
            "block without CRC",
        ),
    ]
}

#[test]
fn every_mode_moves_every_size_both_ways() {
    for (config, name) in modes() {
        for len in [
            0usize,
            1,
            3,
            4,
            5,
            7,
            8,
            13,
            14,
            15,
            127 * 7,
            127 * 7 + 1,
            5000,
        ] {
            let mut p = Pair::new(config.clone(), ServerConfig::default(), Faults::default());
            let data: Vec<u8> = (0..len).map(|i| (i * 31 + len) as u8).collect();
            p.download(DOMAIN, &data)
                .unwrap_or_else(|e| panic!("{name}, {len} bytes: {e}"));
            assert_eq!(
                p.dict.read(0x2000, 0).unwrap(),
                &data[..],
                "{name}, {len} bytes"
            );
            assert_eq!(p.upload(DOMAIN).unwrap(), data, "{name}, {len} bytes");
        }
    }
}

#[test]
fn typed_values_and_refusals_end_to_end() {
    let mut p = Pair::new(
        ClientConfig::default(),
        ServerConfig::default(),
        Faults::default(),
    );
    p.download(HEARTBEAT, &1000u16.to_le_bytes()).unwrap();
    assert_eq!(p.dict.read_value(0x1017, 0).unwrap(), Value::Uint(1000));
    assert_eq!(
        p.upload(Address::new(0x1000, 0)).unwrap(),
        0x0002_0192u32.to_le_bytes()
    );
    for (mux, data, code) in [
        (Address::new(0x1000, 0), vec![0u8; 4], AbortCode::ReadOnly),
        (Address::new(0x3000, 0), vec![0u8; 4], AbortCode::NoObject),
        (Address::new(0x1017, 1), vec![0u8; 2], AbortCode::NoSubIndex),
        (HEARTBEAT, vec![0u8; 3], AbortCode::LengthTooHigh),
    ] {
        let before = p.dict.clone();
        match p.download(mux, &data) {
            Err(SdoClientError::Aborted {
                code: c,
                by_server: true,
                ..
            }) => assert_eq!(c, code),
            other => panic!("{mux:?}: {other:?}"),
        }
        assert_eq!(p.dict, before);
    }
}

#[test]
fn a_lost_answer_times_out_on_both_sides() {
    let faults = Faults {
        drop: 1000,
        ..Faults::default()
    };
    let mut p = Pair::new(ClientConfig::default(), ServerConfig::default(), faults);
    let before = p.dict.clone();
    match p.download(DOMAIN, &[1, 2, 3, 4, 5, 6, 7, 8, 9]) {
        Err(SdoClientError::Aborted {
            code: AbortCode::Timeout,
            by_server: false,
            ..
        }) => {}
        other => panic!("{other:?}"),
    }
    p.settle();
    assert!(!p.server.is_busy());
    assert_eq!(p.dict, before);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Through a channel that drops, duplicates and reorders frames, a transfer either delivers exactly
    /// the value sent or ends in an abort; the dictionary never holds anything but the old or the new
    /// value, and nothing panics.
    #[test]
    fn lossy_channel_never_gives_a_wrong_value(
        len in 0usize..600,
        fill in any::<u8>(),
        mode in 0usize..3,
        drop in 0u16..80,
        duplicate in 0u16..80,
        reorder in 0u16..80,
        seed in any::<u64>(),
        upload_first in any::<bool>(),
    ) {
        let (config, _) = modes()[mode].clone();
        // Without the CRC, block transfer cannot tell a duplicated or late frame from a segment (a
        // duplicated initiate response `C6 …` reads as segment 70, last): CiA 301 gives it nothing to
        // detect that with. Those channels are tried with the CRC and with segmented transfer only.
        let (duplicate, reorder) = if mode == 2 { (0, 0) } else { (duplicate, reorder) };
        let faults = Faults { drop, duplicate, reorder, seed };
        let mut p = Pair::new(config, ServerConfig::default(), faults);
        let old: Vec<u8> = vec![0xEE; 10];
        p.dict.store(0x2000, 0, &old).unwrap();
        let new: Vec<u8> = (0..len).map(|i| fill.wrapping_add(i as u8)).collect();
        if upload_first {
            if let Ok(bytes) = p.upload(DOMAIN) {
                prop_assert_eq!(bytes, old.clone());
            }
            p.settle();
        }
        let result = p.download(DOMAIN, &new);
        p.settle();
        let now = p.dict.read(0x2000, 0).unwrap().to_vec();
        if result.is_ok() {
            prop_assert_eq!(&now, &new);
        } else {
            prop_assert!(now == old || now == new, "neither old nor new: {:?}", now);
        }
        prop_assert!(!p.server.is_busy());
        if let Ok(bytes) = p.upload(DOMAIN) {
            prop_assert_eq!(bytes, now);
        }
    }
}
