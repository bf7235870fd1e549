//! The device hook: a model behind its dictionary for SDO, CoE (complete access) and process data,
//! and process images decoded from the mapping objects.

use std::time::{Duration, Instant};

use od::coe::server::CoeServer;
use od::hook::{Bound, DeviceHook, ImageEntry, ImageError, ProcessImage};
use od::sdo::server::ServerConfig;
use od::sdo::store::ObjectStore;
use od::{
    AbortCode, AccessType, Address, DataType, Dictionary, Object, ObjectKind, SubObject, Value,
};

/// A model owning 0x6000 (two inputs it computes) and 0x7000 (three outputs it takes; it refuses an
/// output of 0xFF in 0x7000:02).
#[derive(Default)]
struct Model {
    inputs: [u16; 2],
    outputs: [u8; 3],
    writes: Vec<(Address, Vec<u8>)>,
    /// The instant each accepted write carried.
    times: Vec<Instant>,
}

impl DeviceHook for Model {
    fn owns(&self, index: u16) -> bool {
        matches!(index, 0x6000 | 0x7000)
    }

    fn read(&self, at: Address, out: &mut [u8; 8]) -> Option<usize> {
        match (at.index, at.sub) {
            (0x6000, 1..=2) => {
                out[..2].copy_from_slice(&self.inputs[usize::from(at.sub) - 1].to_le_bytes());
                Some(2)
            }
            (0x7000, 1..=3) => {
                out[0] = self.outputs[usize::from(at.sub) - 1];
                Some(1)
            }
            _ => None,
        }
    }

    fn check(&self, at: Address, data: &[u8]) -> Result<(), AbortCode> {
        if at == Address::new(0x7000, 2) && data == [0xFF] {
            return Err(AbortCode::InvalidValue);
        }
        Ok(())
    }

    fn write(&mut self, at: Address, data: &[u8], now: Instant) -> Result<(), AbortCode> {
        self.check(at, data)?;
        self.times.push(now);
        if at.index == 0x7000 {
            self.outputs[usize::from(at.sub) - 1] = data[0];
        }
        self.writes.push((at, data.to_vec()));
        Ok(())
    }
}

fn record(index: u16, name: &str, entries: &[(&str, DataType, AccessType)]) -> Object {
    let mut o = Object::structured(index, name, ObjectKind::Record).with_sub(
        0,
        SubObject::new("n", DataType::Unsigned8, AccessType::Ro)
            .with_default(Value::Uint(entries.len() as u64)),
    );
    for (k, (n, t, a)) in entries.iter().enumerate() {
        o = o.with_sub(k as u8 + 1, SubObject::new(*n, *t, *a));
    }
    o
}

fn mapping(index: u16, words: &[u32]) -> Object {
    let mut o = Object::structured(index, "mapping", ObjectKind::Record).with_sub(
        0,
        SubObject::new("n", DataType::Unsigned8, AccessType::Rw)
            .with_default(Value::Uint(words.len() as u64)),
    );
    for (k, w) in words.iter().enumerate() {
        o = o.with_sub(
            k as u8 + 1,
            SubObject::new("e", DataType::Unsigned32, AccessType::Rw)
                .with_default(Value::Uint(u64::from(*w))),
        );
    }
    o
}

fn dict() -> Dictionary {
    let mut d = Dictionary::new();
    d.insert(record(
        0x6000,
        "Inputs",
        &[
            ("a", DataType::Unsigned16, AccessType::Ro),
            ("b", DataType::Unsigned16, AccessType::Ro),
        ],
    ));
    d.insert(record(
        0x7000,
        "Outputs",
        &[
            ("x", DataType::Unsigned8, AccessType::Rw),
            ("y", DataType::Unsigned8, AccessType::Rw),
            ("z", DataType::Unsigned8, AccessType::Rw),
        ],
    ));
    d.insert(record(
        0x6001,
        "Bits",
        &[
            ("on", DataType::Boolean, AccessType::Ro),
            ("ready", DataType::Boolean, AccessType::Ro),
        ],
    ));
    // RxPDO: 0x7000:01, 4 bits of padding (dummy UNSIGNED8 cut to 4), 0x7000:02 at bit 12.
    d.insert(mapping(0x1600, &[0x7000_0108, 0x0005_0004, 0x7000_0208]));
    // TxPDOs: 0x6000:02, then 0x6001:01 and 0x6001:02 as single bits.
    d.insert(mapping(0x1A00, &[0x6000_0210]));
    d.insert(mapping(0x1A01, &[0x6001_0101, 0x6001_0201]));
    let mut assign = Object::structured(0x1C13, "TxPDO assign", ObjectKind::Array).with_sub(
        0,
        SubObject::new("n", DataType::Unsigned8, AccessType::Rw).with_default(Value::Uint(2)),
    );
    for (k, m) in [0x1A00u64, 0x1A01].iter().enumerate() {
        assign = assign.with_sub(
            k as u8 + 1,
            SubObject::new("pdo", DataType::Unsigned16, AccessType::Rw)
                .with_default(Value::Uint(*m)),
        );
    }
    d.insert(assign);
    d
}

#[test]
fn sdo_upload_answers_the_model_and_download_reaches_it() {
    let mut d = dict();
    let mut m = Model {
        inputs: [0x1234, 0xBEEF],
        ..Model::default()
    };
    let t = Instant::now();
    let mut b = Bound::new(&mut d, &mut m, t);
    assert_eq!(b.upload(Address::new(0x6000, 2)), Ok(vec![0xEF, 0xBE]));
    // Read-only for SDO: refused by the dictionary before the model sees it.
    assert_eq!(
        b.download(Address::new(0x6000, 1), &[1, 0]),
        Err(AbortCode::ReadOnly)
    );
    assert_eq!(
        b.download(Address::new(0x7000, 1), &[1, 2]),
        Err(AbortCode::LengthTooHigh)
    );
    assert_eq!(b.download(Address::new(0x7000, 1), &[0x42]), Ok(()));
    // The model refuses: nothing changes, in the model or in the dictionary.
    assert_eq!(
        b.download(Address::new(0x7000, 2), &[0xFF]),
        Err(AbortCode::InvalidValue)
    );
    assert_eq!(d.read(0x7000, 1).unwrap(), &[0x42]);
    assert_eq!(d.read(0x7000, 2).unwrap(), &[0]);
    assert_eq!(m.outputs, [0x42, 0, 0]);
    // The one accepted write reached the model with the request's instant.
    assert_eq!(m.times, vec![t]);
    assert_eq!(m.writes, vec![(Address::new(0x7000, 1), vec![0x42])]);
}

#[test]
fn an_image_from_an_assignment_packs_bits_without_gaps() {
    let d = dict();
    let image = ProcessImage::from_assignment(&d, 0x1C13).unwrap();
    assert_eq!(
        image.entries(),
        &[
            ImageEntry {
                at: Address::new(0x6000, 2),
                bit: 0,
                bits: 16
            },
            ImageEntry {
                at: Address::new(0x6001, 1),
                bit: 16,
                bits: 1
            },
            ImageEntry {
                at: Address::new(0x6001, 2),
                bit: 17,
                bits: 1
            },
        ]
    );
    assert_eq!((image.bits(), image.len()), (18, 3));
    assert!(!image.is_empty());
    assert!(ProcessImage::default().is_empty());
    let mut d = d;
    d.store(0x6001, 2, &[1]).unwrap();
    let m = Model {
        inputs: [0, 0xA55A],
        ..Model::default()
    };
    let mut out = [0xFFu8; 3];
    image.pack(&d, &m, &mut out);
    // 0x6000:02 from the model, then bit 16 = 0x6001:01 (0), bit 17 = 0x6001:02 (1).
    assert_eq!(out, [0x5A, 0xA5, 0b10]);
}

/// An assignment entry 0 among the counted ones assigns nothing: the count 2 with the entries
/// 0x1A00 and 0 gives 0x1A00's image alone.
#[test]
fn an_assignment_entry_0_assigns_nothing() {
    let mut d = dict();
    let one = ProcessImage::from_mapping(&d, 0x1A00).unwrap();
    assert_eq!(one.bits(), 16);
    d.store(0x1C13, 2, &[0, 0]).unwrap();
    assert_eq!(ProcessImage::from_assignment(&d, 0x1C13), Ok(one));
}

#[test]
fn a_mapping_that_is_not_there_is_named() {
    let mut d = dict();
    assert_eq!(
        ProcessImage::from_mapping(&d, 0x1601),
        Err(ImageError::Missing {
            index: 0x1601,
            sub: 0
        })
    );
    // An assignment naming a mapping object that is not there, at its first entry.
    d.store(0x1C13, 1, &0x1A05u16.to_le_bytes()).unwrap();
    assert_eq!(
        ProcessImage::from_assignment(&d, 0x1C13),
        Err(ImageError::Missing {
            index: 0x1A05,
            sub: 0
        })
    );
    assert_eq!(
        ImageError::Missing {
            index: 0x1A05,
            sub: 0
        }
        .to_string(),
        "0x1A05:00, a PDO mapping or assignment entry, is not in the dictionary"
    );
}

#[test]
fn unpack_delivers_mapped_entries_and_skips_padding() {
    let mut d = dict();
    let image = ProcessImage::from_mapping(&d, 0x1600).unwrap();
    assert_eq!((image.bits(), image.len()), (20, 3));
    assert!(image.entries()[1].is_padding());
    let mut m = Model::default();
    // 0x7000:01 = 0x11 (bits 0–7), padding bits 8–11, 0x7000:02 = 0x3C (bits 12–19).
    let t1 = Instant::now();
    let (t2, t3) = (t1 + Duration::from_secs(1), t1 + Duration::from_secs(2));
    image.unpack(&[0x11, 0xCF, 0x03], &mut d, &mut m, t1);
    assert_eq!(m.outputs, [0x11, 0x3C, 0]);
    assert_eq!(d.read(0x7000, 2).unwrap(), &[0x3C]);
    // A value the model refuses is dropped, in the dictionary too.
    image.unpack(&[0x12, 0xF0, 0x0F], &mut d, &mut m, t2);
    assert_eq!(m.outputs, [0x12, 0x3C, 0]);
    assert_eq!(d.read(0x7000, 2).unwrap(), &[0x3C]);
    // A short image delivers the entries it holds whole.
    image.unpack(&[0x13], &mut d, &mut m, t3);
    assert_eq!(m.outputs, [0x13, 0x3C, 0]);
    // Each accepted entry with the instant of its image (0x7000:02 = 0xFF at t2 refused).
    assert_eq!(m.times, vec![t1, t1, t2, t3]);
}

/// A CoE mailbox: header (length, address 0, channel 0, priority 0, type 3 CoE, `counter`), CoE
/// header (SDO request), then `sdo`.
fn coe(counter: u8, sdo: &[u8]) -> Vec<u8> {
    let mut m = Vec::new();
    m.extend_from_slice(&((sdo.len() + 2) as u16).to_le_bytes());
    m.extend_from_slice(&[0, 0, 0, counter << 4 | 0x03]);
    m.extend_from_slice(&[0x00, 0x20]);
    m.extend_from_slice(sdo);
    m
}

#[test]
fn complete_access_goes_through_the_model() {
    let mut d = dict();
    let mut m = Model {
        inputs: [0x0102, 0x0304],
        ..Model::default()
    };
    let mut server = CoeServer::new(ServerConfig::default(), 128);
    let now = Instant::now();
    // Upload 0x6000 complete from sub-index 0: ccs 2, complete access (bit 4).
    server.handle_mailbox(
        now,
        &coe(1, &[0x50, 0x00, 0x60, 0x00, 0, 0, 0, 0]),
        &mut Bound::new(&mut d, &mut m, now),
    );
    let answer = server.poll_transmit().unwrap();
    // Sub-index 0 as 16 bits and two UNSIGNED16 are 6 bytes, more than an expedited response holds:
    // a normal upload response (scs 2, size indicated, the complete-access bit echoed) with the size
    // and the data, sub-index 0 = 2 and padding, then 0x0102 and 0x0304 from the model.
    assert_eq!(
        &answer[8..],
        &[0x51, 0x00, 0x60, 0x00, 6, 0, 0, 0, 2, 0, 0x02, 0x01, 0x04, 0x03]
    );
    // Download 0x7000 complete from sub-index 1 (x, y, z): y = 0xFF is
    // refused by the model, and nothing is written.
    server.handle_mailbox(
        now,
        &coe(2, &[0x37, 0x00, 0x70, 0x01, 0x07, 0xFF, 0x00, 0x00]),
        &mut Bound::new(&mut d, &mut m, now),
    );
    let answer = server.poll_transmit().unwrap();
    assert_eq!(
        &answer[8..],
        &[0x80, 0x00, 0x70, 0x01, 0x30, 0x00, 0x09, 0x06]
    );
    assert_eq!(m.writes, vec![]);
    assert_eq!(d.read(0x7000, 1).unwrap(), &[0]);
    // Accepted: every entry reaches the model in sub-index order, and the dictionary.
    let later = now + Duration::from_millis(5);
    server.handle_mailbox(
        later,
        &coe(3, &[0x37, 0x00, 0x70, 0x01, 0x07, 0x08, 0x09, 0x00]),
        &mut Bound::new(&mut d, &mut m, now),
    );
    let answer = server.poll_transmit().unwrap();
    assert_eq!(&answer[8..], &[0x70, 0x00, 0x70, 0x01, 0, 0, 0, 0]);
    assert_eq!(
        m.writes,
        vec![
            (Address::new(0x7000, 1), vec![7]),
            (Address::new(0x7000, 2), vec![8]),
            (Address::new(0x7000, 3), vec![9]),
        ]
    );
    assert_eq!(m.outputs, [7, 8, 9]);
    assert_eq!(d.read(0x7000, 3).unwrap(), &[9]);
    // Each with the instant the mailbox arrived, the server's, not the borrowed objects'.
    assert_eq!(m.times, vec![later; 3]);
}
