//! The SDO Information service (ETG.1000.6 §5.6.3) of the CoE server, on the SMD23K-B dictionary of
//! the fixture ESI, byte by byte.

use std::time::Instant;

use od::coe::CoeServer;
use od::sdo::ServerConfig;
use od::Dictionary;

fn smd() -> Dictionary {
    let path = format!(
        "{}/../fixtures/smd/SMD23K-B_SMD24K.esi.xml",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read(&path).unwrap();
    let select = od::esi::Select::Name("SMD23K-B".into());
    let desc = od::esi::read(&text, "SMD23K-B_SMD24K.esi.xml", Some(&select)).unwrap();
    desc.dictionary
}

thread_local! {
    static COUNTER: std::cell::Cell<u8> = const { std::cell::Cell::new(0) };
}

/// A CoE SDO Information request with the next counter (1–7): mailbox header, CoE header (service 8), the info
/// header (OpCode, reserved, fragments left 0), the request's data.
fn request(op: u8, data: &[u8]) -> Vec<u8> {
    let mut m = ((2 + 4 + data.len()) as u16).to_le_bytes().to_vec();
    let counter = COUNTER.with(|c| {
        c.set(c.get() % 7 + 1);
        c.get()
    });
    m.extend_from_slice(&[0, 0, 0, 0x03 | counter << 4, 0x00, 0x80, op, 0, 0, 0]);
    m.extend_from_slice(data);
    m
}

/// Serves `m`, returns every mailbox the server answers with.
fn serve(s: &mut CoeServer, d: &mut Dictionary, m: &[u8]) -> Vec<Vec<u8>> {
    s.handle_mailbox(Instant::now(), m, d);
    std::iter::from_fn(|| s.poll_transmit()).collect()
}

/// (OpCode with Incomplete, fragments left, data) of an SDO Information answer.
fn split(m: &[u8]) -> (u8, u16, Vec<u8>) {
    let len = usize::from(u16::from_le_bytes([m[0], m[1]]));
    assert_eq!(m[5] & 0x0F, 0x03, "CoE");
    assert_eq!(m[6..8], [0x00, 0x80], "CoE service 8, SDO Information");
    (
        m[8],
        u16::from_le_bytes([m[10], m[11]]),
        m[12..6 + len].to_vec(),
    )
}

#[test]
fn od_list_lengths_and_all_objects() {
    let mut d = smd();
    let mut s = CoeServer::new(ServerConfig::default(), 128);
    let all: Vec<u16> = d.objects().map(|o| o.index).collect();
    let answers = serve(&mut s, &mut d, &request(1, &[0, 0]));
    assert_eq!(answers.len(), 1);
    let (op, left, data) = split(&answers[0]);
    assert_eq!((op, left), (0x02, 0));
    // ListType 0, then the lengths of: all, RxPDO-mappable (0x7000), TxPDO-mappable (0x6000),
    // device replacement, start-up parameters.
    let mut expect = vec![0, 0];
    for n in [all.len() as u16, 1, 1, 0, 0] {
        expect.extend_from_slice(&n.to_le_bytes());
    }
    assert_eq!(data, expect);
    let (_, _, data) = split(&serve(&mut s, &mut d, &request(1, &[2, 0]))[0]);
    assert_eq!(data, [0x02, 0x00, 0x00, 0x70]);
    let (_, _, data) = split(&serve(&mut s, &mut d, &request(1, &[1, 0]))[0]);
    let listed: Vec<u16> = data[2..]
        .chunks(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]))
        .collect();
    assert_eq!(listed, all);
    assert!(listed.contains(&0x8010) && listed.contains(&0x1018));
}

/// A list longer than the mailbox comes in fragments: Incomplete on all but the last, Fragments
/// Left counting down, ListType only in the first; each mailbox has the next counter.
#[test]
fn a_long_list_is_fragmented() {
    let mut d = smd();
    let all: Vec<u16> = d.objects().map(|o| o.index).collect();
    // 24-byte mailboxes: 12 bytes of data per fragment.
    let mut s = CoeServer::new(ServerConfig::default(), 24);
    let answers = serve(&mut s, &mut d, &request(1, &[1, 0]));
    let total = 2 + 2 * all.len();
    let n = total.div_ceil(24 - 12);
    assert_eq!(answers.len(), n);
    let mut joined = Vec::new();
    for (k, m) in answers.iter().enumerate() {
        assert!(m.len() <= 24);
        let (op, left, data) = split(m);
        let last = k + 1 == n;
        assert_eq!(op, if last { 0x02 } else { 0x82 }, "fragment {k}");
        assert_eq!(usize::from(left), n - 1 - k);
        assert_eq!((m[5] >> 4) & 0x07, (k % 7) as u8 + 1, "counter");
        joined.extend(data);
    }
    assert_eq!(joined[..2], [1, 0]);
    assert_eq!(joined.len(), total);
}

#[test]
fn object_and_entry_descriptions() {
    let mut d = smd();
    let mut s = CoeServer::new(ServerConfig::default(), 128);
    // 0x1018: RECORD (9), type IDENTITY 0x0023, max sub-index 4, name.
    let (op, _, data) = split(&serve(&mut s, &mut d, &request(3, &[0x18, 0x10]))[0]);
    assert_eq!(op, 0x04);
    assert_eq!(data[..6], [0x18, 0x10, 0x23, 0x00, 0x04, 0x09]);
    assert_eq!(
        std::str::from_utf8(&data[6..]).unwrap(),
        d.object(0x1018).unwrap().name
    );
    // 0x1008: VAR (7) VISIBLE_STRING (0x0009).
    let (_, _, data) = split(&serve(&mut s, &mut d, &request(3, &[0x08, 0x10]))[0]);
    assert_eq!(data[..6], [0x08, 0x10, 0x09, 0x00, 0x00, 0x07]);
    // 0x6000:01 STATUS_word0: UNSIGNED16, 16 bits, readable in every state, TxPDO-mappable.
    let (op, _, data) = split(&serve(&mut s, &mut d, &request(5, &[0x00, 0x60, 0x01, 0x00]))[0]);
    assert_eq!(op, 0x06);
    assert_eq!(
        data[..10],
        [0x00, 0x60, 0x01, 0x00, 0x06, 0x00, 0x10, 0x00, 0x87, 0x00]
    );
    assert_eq!(&data[10..], b"STATUS_word0");
    // 0x8010:03 Starting_Speed: UNSIGNED32, read and write in every state, not mappable.
    let (_, _, data) = split(&serve(&mut s, &mut d, &request(5, &[0x10, 0x80, 0x03, 0x00]))[0]);
    assert_eq!(
        data[..10],
        [0x10, 0x80, 0x03, 0x00, 0x07, 0x00, 0x20, 0x00, 0x3F, 0x00]
    );
    assert_eq!(&data[10..], b"Starting_Speed");
}

/// An object or entry that is not there, an unknown list or OpCode, a cut request: SDO Info Error
/// (OpCode 7) with the abort code; SDO transfers go on.
#[test]
fn refusals_are_sdo_info_errors() {
    let mut d = smd();
    let mut s = CoeServer::new(ServerConfig::default(), 128);
    for (req, code) in [
        (request(3, &[0x00, 0x20]), 0x0602_0000u32),
        (request(5, &[0x10, 0x80, 0x09, 0x00]), 0x0609_0011),
        (request(1, &[9, 0]), 0x0601_0000),
        (request(0x11, &[]), 0x0504_0001),
        (request(3, &[0x18]), 0x0504_0001),
    ] {
        let answers = serve(&mut s, &mut d, &req);
        let (op, left, data) = split(&answers[0]);
        assert_eq!((op, left), (0x07, 0));
        assert_eq!(data, code.to_le_bytes(), "{req:02X?}");
    }
    // An expedited upload of 0x1018:02 afterwards.
    let up = [
        0x0A, 0, 0, 0, 0, 0x03, 0x00, 0x20, 0x40, 0x18, 0x10, 0x02, 0, 0, 0, 0,
    ];
    let answers = serve(&mut s, &mut d, &up);
    assert_eq!(
        answers[0][8..16],
        [0x43, 0x18, 0x10, 0x02, 0x01, 0x23, 0, 0]
    );
}

/// The client side of SDO Information (requests, fragments joined, descriptions read) against the
/// server, on every object and entry of the SMD23K-B: what comes back is the dictionary's.
#[test]
fn the_client_side_reads_back_the_whole_dictionary() {
    use od::coe::info::{self, EntryDescription, ObjectDescription, OdList, Reassembly, Request};
    let mut d = smd();
    // A small mailbox: the list and the long names come in fragments.
    let mut s = CoeServer::new(ServerConfig::default(), 32);
    let mut ask = |d: &mut Dictionary, r: Request| {
        let mut m = ((info::request(r).len()) as u16).to_le_bytes().to_vec();
        m.extend_from_slice(&[0, 0, 0, 0x03]);
        m.extend_from_slice(&info::request(r));
        let mut whole = Reassembly::new();
        let answers = serve(&mut s, d, &m);
        let n = answers.len();
        for (k, a) in answers.iter().enumerate() {
            let len = usize::from(u16::from_le_bytes([a[0], a[1]]));
            match whole.push(&a[6..6 + len]) {
                Ok(Some(done)) => {
                    assert_eq!(k + 1, n, "the last fragment ends the answer");
                    return Ok(done);
                }
                Ok(None) => {}
                Err(e) => return Err(e),
            }
        }
        panic!("{n} fragments and no end");
    };
    let (_, list) = ask(&mut d, Request::OdList(OdList::All)).unwrap();
    let indices = info::od_list_indices(OdList::All, &list).unwrap();
    let all: Vec<u16> = d.objects().map(|o| o.index).collect();
    assert_eq!(indices, all);
    let mut entries = 0;
    for &index in &indices {
        let (op, data) = ask(&mut d, Request::Object(index)).unwrap();
        assert_eq!(op, info::opcode::OBJECT);
        let o = ObjectDescription::parse(&data).unwrap();
        let object = d.object(index).unwrap().clone();
        assert_eq!((o.index, o.name.as_str()), (index, object.name.as_str()));
        for (&sub, e) in &object.subs {
            let (op, data) = ask(
                &mut d,
                Request::Entry {
                    index,
                    sub,
                    value_info: 0,
                },
            )
            .unwrap();
            assert_eq!(op, info::opcode::ENTRY);
            let got = EntryDescription::parse(&data).unwrap();
            assert_eq!((got.index, got.sub), (index, sub));
            assert_eq!(got.name, e.name, "{index:04X}:{sub:02X}");
            assert_eq!(info::data_type(got.data_type), Some(e.data_type));
            entries += 1;
        }
    }
    // The SMD23K-B of the fixture ESI has 60 entries: none was left out of the loop.
    assert_eq!(entries, 60);
    // A missing object is an SDO Info Error with its code.
    assert_eq!(
        ask(&mut d, Request::Object(0x5555)),
        Err(info::InfoError::Refused(od::AbortCode::NoObject))
    );
}

/// ValueInfo (ETG.1000.6 §5.6.3.6): of the unit, default, minimum and maximum asked for, the answer
/// gives those the entry has, each of the entry's size after the access and before the name.
#[test]
fn entry_descriptions_give_the_values_asked_for() {
    use od::coe::info::EntryDescription;
    let mut d = smd();
    let mut s = CoeServer::new(ServerConfig::default(), 128);
    // 0x8010:03 Starting_Speed has a default (141) and no unit or limits: ValueInfo 0x78 asked,
    // 0x10 answered.
    let (_, _, data) = split(&serve(&mut s, &mut d, &request(5, &[0x10, 0x80, 0x03, 0x78]))[0]);
    assert_eq!(
        data[..14],
        [0x10, 0x80, 0x03, 0x10, 0x07, 0x00, 0x20, 0x00, 0x3F, 0x00, 0x8D, 0x00, 0x00, 0x00]
    );
    assert_eq!(&data[14..], b"Starting_Speed");
    // With a unit (mV) and limits 1..1999999 given to it: all four, in their order.
    {
        let e = d.object_mut(0x8010).unwrap().subs.get_mut(&3).unwrap();
        e.unit = Some(0xFD26_0000);
        e.low = Some(od::Value::Uint(1));
        e.high = Some(od::Value::Uint(1_999_999));
    }
    let (_, _, data) = split(&serve(&mut s, &mut d, &request(5, &[0x10, 0x80, 0x03, 0x78]))[0]);
    assert_eq!(
        data[..30],
        [
            0x10, 0x80, 0x03, 0x78, 0x07, 0x00, 0x20, 0x00, 0x3F, 0x00, // header, access
            0x00, 0x00, 0x26, 0xFD, // unit
            0x8D, 0x00, 0x00, 0x00, // default 141
            0x01, 0x00, 0x00, 0x00, // minimum 1
            0x7F, 0x84, 0x1E, 0x00, // maximum 1,999,999
            b'S', b't', b'a', b'r',
        ]
    );
    let e = EntryDescription::parse(&data).unwrap();
    assert_eq!(e.unit, Some(0xFD26_0000));
    assert_eq!(e.default, Some(vec![0x8D, 0, 0, 0]));
    assert_eq!(e.min, Some(vec![1, 0, 0, 0]));
    assert_eq!(e.max, Some(vec![0x7F, 0x84, 0x1E, 0x00]));
    assert_eq!(e.name, "Starting_Speed");
    // Only the minimum asked for: only it.
    let (_, _, data) = split(&serve(&mut s, &mut d, &request(5, &[0x10, 0x80, 0x03, 0x20]))[0]);
    assert_eq!(data[3], 0x20);
    assert_eq!(data[10..14], [0x01, 0x00, 0x00, 0x00]);
    assert_eq!(&data[14..], b"Starting_Speed");
    // A string gives no values: 0x1008's default is not sent.
    let (_, _, data) = split(&serve(&mut s, &mut d, &request(5, &[0x08, 0x10, 0x00, 0x10]))[0]);
    assert_eq!(data[3], 0x00);
    assert_eq!(&data[10..], b"Device name");
}
