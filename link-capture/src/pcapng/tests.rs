//! The blocks' bytes as draft-tuexen-opsawg-pcapng-05 lays them out, worked out by hand, and
//! files of other writers (big-endian, microseconds, the obsolete and simple packet blocks) read.

use std::time::{Duration, SystemTime, UNIX_EPOCH};

use super::*;

/// 2023-11-14 22:13:20.123456789 UTC: 1,700,000,000,123,456,789 ns = 0x17979CFE_3D85CD15.
fn t1() -> SystemTime {
    UNIX_EPOCH + Duration::new(1_700_000_000, 123_456_789)
}

/// The SocketCAN bytes of an SDO upload request to node 5 (0x605, 0x1018:01): the identifier
/// 0x00000605 in network byte order, length 8, three zeros, the 8 data bytes.
const REQUEST: [u8; 16] = [
    0x00, 0x00, 0x06, 0x05, 0x08, 0x00, 0x00, 0x00, 0x40, 0x18, 0x10, 0x01, 0x00, 0x00, 0x00, 0x00,
];
/// Its answer (0x585): vendor-ID 0x00000AC1.
const ANSWER: [u8; 16] = [
    0x00, 0x00, 0x05, 0x85, 0x08, 0x00, 0x00, 0x00, 0x43, 0x18, 0x10, 0x01, 0xC1, 0x0A, 0x00, 0x00,
];

/// A whole file of two frames, byte for byte: the Section Header Block (little-endian, version
/// 1.0, section length −1, shb_userappl "sdo-tool"), the Interface Description Block of vcan0
/// (LINKTYPE_CAN_SOCKETCAN 227 = 0xE3, snapshot length 0, if_name "vcan0" padded to 8 bytes,
/// if_tsresol 9), and two Enhanced Packet Blocks: the request sent (epb_flags 0b10) at t1 and the
/// answer received (0b01) 250 µs later (0x17979CFE_3D899DA5 ns).
#[test]
fn two_frames_golden() {
    let mut out = Vec::new();
    section_header(&mut out, "sdo-tool");
    interface_description(&mut out, LINKTYPE_CAN_SOCKETCAN, "vcan0");
    enhanced_packet(&mut out, 0, t1(), Direction::Outbound, &REQUEST);
    let t2 = t1() + Duration::from_micros(250);
    enhanced_packet(&mut out, 0, t2, Direction::Inbound, &ANSWER);
    #[rustfmt::skip]
    let expected: Vec<u8> = [
        // Section Header Block: 44 bytes.
        &[0x0A, 0x0D, 0x0D, 0x0A, 0x2C, 0x00, 0x00, 0x00][..],
        &[0x4D, 0x3C, 0x2B, 0x1A, 0x01, 0x00, 0x00, 0x00],
        &[0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF],
        &[0x04, 0x00, 0x08, 0x00, b's', b'd', b'o', b'-', b't', b'o', b'o', b'l'],
        &[0x00, 0x00, 0x00, 0x00],
        &[0x2C, 0x00, 0x00, 0x00],
        // Interface Description Block: 44 bytes.
        &[0x01, 0x00, 0x00, 0x00, 0x2C, 0x00, 0x00, 0x00],
        &[0xE3, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00],
        &[0x02, 0x00, 0x05, 0x00, b'v', b'c', b'a', b'n', b'0', 0x00, 0x00, 0x00],
        &[0x09, 0x00, 0x01, 0x00, 0x09, 0x00, 0x00, 0x00],
        &[0x00, 0x00, 0x00, 0x00],
        &[0x2C, 0x00, 0x00, 0x00],
        // Enhanced Packet Block, outbound: 60 bytes.
        &[0x06, 0x00, 0x00, 0x00, 0x3C, 0x00, 0x00, 0x00],
        &[0x00, 0x00, 0x00, 0x00],
        &[0xFE, 0x9C, 0x97, 0x17, 0x15, 0xCD, 0x85, 0x3D],
        &[0x10, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x00],
        &REQUEST,
        &[0x02, 0x00, 0x04, 0x00, 0x02, 0x00, 0x00, 0x00],
        &[0x00, 0x00, 0x00, 0x00],
        &[0x3C, 0x00, 0x00, 0x00],
        // Enhanced Packet Block, inbound: 60 bytes.
        &[0x06, 0x00, 0x00, 0x00, 0x3C, 0x00, 0x00, 0x00],
        &[0x00, 0x00, 0x00, 0x00],
        &[0xFE, 0x9C, 0x97, 0x17, 0xA5, 0x9D, 0x89, 0x3D],
        &[0x10, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x00],
        &ANSWER,
        &[0x02, 0x00, 0x04, 0x00, 0x01, 0x00, 0x00, 0x00],
        &[0x00, 0x00, 0x00, 0x00],
        &[0x3C, 0x00, 0x00, 0x00],
    ]
    .concat();
    assert_eq!(out, expected);

    let mut r = Reader::new(&out[..]);
    let p = r.next_packet().unwrap().unwrap();
    assert_eq!(
        (p.interface, p.link_type, p.data, p.time, p.direction),
        (0, 227, &REQUEST[..], Some(t1()), Some(Direction::Outbound))
    );
    let p = r.next_packet().unwrap().unwrap();
    assert_eq!((p.data, p.time), (&ANSWER[..], Some(t2)));
    assert_eq!(p.direction, Some(Direction::Inbound));
    assert!(r.next_packet().unwrap().is_none());
    assert_eq!((r.skipped(), r.unknown_interface()), (0, 0));
    assert_eq!(
        r.interfaces_seen(),
        [InterfaceInfo {
            link_type: 227,
            name: Some("vcan0".into()),
            tsresol: 9,
            tsoffset: 0
        }]
    );
}

/// Without an application, the Section Header Block has no options (28 bytes); an interface
/// without a name has only if_tsresol; a frame of 1 byte is padded to 4, its lengths 1.
#[test]
fn blocks_without_options_and_padding() {
    let mut out = Vec::new();
    section_header(&mut out, "");
    assert_eq!(out.len(), 28);
    assert_eq!(&out[4..8], &[28, 0, 0, 0]);
    assert_eq!(&out[24..28], &[28, 0, 0, 0]);
    out.clear();
    interface_description(&mut out, LINKTYPE_ETHERNET, "");
    #[rustfmt::skip]
    assert_eq!(out, [
        0x01, 0, 0, 0, 32, 0, 0, 0,
        0x01, 0, 0, 0, 0, 0, 0, 0,
        0x09, 0, 0x01, 0, 0x09, 0, 0, 0,
        0, 0, 0, 0,
        32, 0, 0, 0,
    ]);
    out.clear();
    enhanced_packet(&mut out, 3, UNIX_EPOCH, Direction::Inbound, &[0xAB]);
    #[rustfmt::skip]
    assert_eq!(out, [
        0x06, 0, 0, 0, 48, 0, 0, 0,
        3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        1, 0, 0, 0, 1, 0, 0, 0,
        0xAB, 0, 0, 0,
        0x02, 0, 0x04, 0, 0x01, 0, 0, 0,
        0, 0, 0, 0,
        48, 0, 0, 0,
    ]);
}

/// epb_flags bits 0–1: 01 inbound, 10 outbound, 00 and 11 none; the other bits do not count.
#[test]
fn directions_and_their_flags() {
    assert_eq!(Direction::Inbound.flags(), 1);
    assert_eq!(Direction::Outbound.flags(), 2);
    assert_eq!(Direction::from_flags(0x0000_0101), Some(Direction::Inbound));
    assert_eq!(
        Direction::from_flags(0xFFFF_FFF2),
        Some(Direction::Outbound)
    );
    assert_eq!(Direction::from_flags(0), None);
    assert_eq!(Direction::from_flags(3), None);
    assert_eq!(nanoseconds(UNIX_EPOCH - Duration::from_secs(1)), 0);
    assert_eq!(nanoseconds(t1()), 0x17979CFE_3D85CD15);
}

/// A big-endian file as another writer makes it, by hand: a section with no options, an Ethernet
/// interface "eth0" with if_tsresol 6 (microseconds) and if_tsoffset 10 s, an Enhanced Packet
/// Block of 3 bytes at 1.000002 s with epb_flags inbound, an obsolete Packet Block (type 2) and a
/// Simple Packet Block (interface 0, no time), a block of an unknown type skipped.
#[test]
fn a_big_endian_file_with_other_blocks() {
    #[rustfmt::skip]
    let file: Vec<u8> = [
        // SHB, 28 bytes, big-endian.
        &[0x0A, 0x0D, 0x0D, 0x0A, 0, 0, 0, 28, 0x1A, 0x2B, 0x3C, 0x4D, 0, 1, 0, 0][..],
        &[0xFF; 8], &[0, 0, 0, 28],
        // IDB, 52 bytes: Ethernet, "eth0", if_tsresol 6, if_tsoffset 10.
        &[0, 0, 0, 1, 0, 0, 0, 52, 0, 1, 0, 0, 0, 0, 0xFF, 0xFF],
        &[0, 2, 0, 4, b'e', b't', b'h', b'0'],
        &[0, 9, 0, 1, 6, 0, 0, 0],
        &[0, 14, 0, 8, 0, 0, 0, 0, 0, 0, 0, 10],
        &[0, 0, 0, 0], &[0, 0, 0, 52],
        // EPB, 44 bytes: 1,000,002 µs, 3 bytes, epb_flags inbound.
        &[0, 0, 0, 6, 0, 0, 0, 44, 0, 0, 0, 0],
        &[0, 0, 0, 0, 0x00, 0x0F, 0x42, 0x42],
        &[0, 0, 0, 3, 0, 0, 0, 3, 0xAA, 0xBB, 0xCC, 0],
        &[0, 2, 0, 4, 0, 0, 0, 1],
        &[0, 0, 0, 44],
        // A block of type 0x0BAD, 16 bytes: skipped.
        &[0, 0, 0x0B, 0xAD, 0, 0, 0, 16, 1, 2, 3, 4, 0, 0, 0, 16],
        // PB, 36 bytes: interface 0, 2 µs, 2 bytes.
        &[0, 0, 0, 2, 0, 0, 0, 36, 0, 0, 0, 0],
        &[0, 0, 0, 0, 0, 0, 0, 2],
        &[0, 0, 0, 2, 0, 0, 0, 2, 0x11, 0x22, 0, 0],
        &[0, 0, 0, 36],
        // SPB, 20 bytes: original length 5, 4 bytes kept (the block holds no more).
        &[0, 0, 0, 3, 0, 0, 0, 20, 0, 0, 0, 5, 1, 2, 3, 4, 0, 0, 0, 20],
    ]
    .concat();
    let mut r = Reader::new(&file[..]);
    let base = UNIX_EPOCH + Duration::from_secs(10);
    let p = r.next_packet().unwrap().unwrap();
    assert_eq!(
        (p.link_type, p.data, p.direction),
        (1, &[0xAA, 0xBB, 0xCC][..], Some(Direction::Inbound))
    );
    assert_eq!(p.time, Some(base + Duration::from_micros(1_000_002)));
    let p = r.next_packet().unwrap().unwrap();
    assert_eq!((p.data, p.direction), (&[0x11, 0x22][..], None));
    assert_eq!(p.time, Some(base + Duration::from_micros(2)));
    let p = r.next_packet().unwrap().unwrap();
    assert_eq!((p.interface, p.data, p.time), (0, &[1, 2, 3, 4][..], None));
    assert!(r.next_packet().unwrap().is_none());
    assert_eq!(r.interfaces_seen()[0].name.as_deref(), Some("eth0"));
    assert_eq!(r.interfaces_seen()[0].tsoffset, 10);
}

/// if_tsresol in powers of ten and of two, an offset back in time, and times no clock has.
#[test]
fn timestamps_in_every_resolution() {
    let s = |secs, nanos| Some(UNIX_EPOCH + Duration::new(secs, nanos));
    assert_eq!(timestamp(1_500_000, 6, 0), s(1, 500_000_000));
    assert_eq!(timestamp(1_500, 3, 0), s(1, 500_000_000));
    assert_eq!(timestamp(15, 1, 0), s(1, 500_000_000));
    assert_eq!(timestamp(7, 0, 0), s(7, 0));
    assert_eq!(timestamp(1_000_000_001, 9, 0), s(1, 1));
    // Picoseconds: the fraction below a nanosecond is dropped.
    assert_eq!(timestamp(2_000_000_000_999, 12, 0), s(2, 0));
    // 2^-10 s: 1536 units are 1.5 s.
    assert_eq!(timestamp(1536, 0x80 | 10, 0), s(1, 500_000_000));
    assert_eq!(timestamp(3, 0x80, 0), s(3, 0));
    assert_eq!(timestamp(10_000_000, 6, -4), s(6, 0));
    assert_eq!(
        timestamp(0, 6, -1),
        UNIX_EPOCH.checked_sub(Duration::from_secs(1))
    );
    // 10^-40 s has no 128-bit count of units per second: time 0.
    assert_eq!(timestamp(5, 40, 0), s(0, 0));
    assert_eq!(timestamp(u64::MAX, 0x80 | 127, 0), s(0, 0));
}

fn minimal(packets: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    section_header(&mut out, "");
    interface_description(&mut out, LINKTYPE_CAN_SOCKETCAN, "can0");
    out.extend_from_slice(packets);
    out
}

fn error(file: &[u8]) -> String {
    let mut r = Reader::new(file);
    loop {
        match r.next_packet() {
            Ok(Some(_)) => {}
            Ok(None) => panic!("read to the end"),
            Err(e) => return e.to_string(),
        }
    }
}

/// What is no pcapng file, or not one this reader reads, is refused naming the block's offset.
#[test]
fn refusals_name_the_block() {
    assert_eq!(
        error(b"(1.0) vcan0 123#00\n"),
        "not a pcapng file (no Section Header Block at its start)"
    );
    assert_eq!(
        error(b"abc"),
        "not a pcapng file (no Section Header Block at its start)"
    );
    let mut shb = Vec::new();
    section_header(&mut shb, "");
    let mut bad = shb.clone();
    bad[8..12].copy_from_slice(&[1, 2, 3, 4]);
    assert_eq!(
        error(&bad),
        "byte 0: the section's byte-order magic is 0x04030201, not 0x1A2B3C4D"
    );
    let mut v2 = shb.clone();
    v2[12] = 2;
    assert_eq!(
        error(&v2),
        "byte 0: pcapng version 2.0 (this reader reads 1.x)"
    );
    let mut odd = minimal(&[]);
    odd.extend_from_slice(&[6, 0, 0, 0, 33, 0, 0, 0]);
    assert_eq!(
        error(&odd),
        "byte 68: block length 33 is not a length of a block of type 0x00000006"
    );
    let mut short = minimal(&[]);
    short.extend_from_slice(&[6, 0, 0, 0, 28, 0, 0, 0]);
    assert_eq!(
        error(&short),
        "byte 68: block length 28 is not a length of a block of type 0x00000006"
    );
    let mut lengths = minimal(&[]);
    lengths.extend_from_slice(&[0x77, 0, 0, 0, 16, 0, 0, 0, 0, 0, 0, 0, 20, 0, 0, 0]);
    assert_eq!(
        error(&lengths),
        "byte 68: the block's lengths differ (16 at its start, 20 at its end)"
    );
    let mut idb = shb.clone();
    idb.extend_from_slice(&[1, 0, 0, 0, 0, 0, 0x10, 0]);
    assert_eq!(
        error(&idb),
        "byte 28: a block of type 0x00000001 of 1048576 bytes (at most 262144 are read)"
    );
    // An option that runs past the block.
    let mut opt = shb.clone();
    #[rustfmt::skip]
    opt.extend_from_slice(&[
        1, 0, 0, 0, 24, 0, 0, 0, 227, 0, 0, 0, 0, 0, 0, 0,
        2, 0, 8, 0, 24, 0, 0, 0,
    ]);
    assert_eq!(
        error(&opt),
        "byte 28: option 2 of 8 bytes runs past the block's end"
    );
    // A packet longer than its block.
    let mut epb = Vec::new();
    enhanced_packet(&mut epb, 0, UNIX_EPOCH, Direction::Inbound, &[1, 2, 3, 4]);
    epb[20] = 200;
    assert_eq!(
        error(&minimal(&epb)),
        "byte 68: a packet of 200 bytes in a block of 48 bytes"
    );
    // 40 bytes: more than the 16 the block holds before its options.
    epb[20] = 40;
    assert_eq!(
        error(&minimal(&epb)),
        "byte 68: a packet of 40 bytes in a block of 48 bytes"
    );
}

/// A file cut inside a block: the packets before it are read, then the cut is named; a file of
/// whole blocks ends without error.
#[test]
fn a_file_cut_short() {
    let mut epb = Vec::new();
    enhanced_packet(&mut epb, 0, t1(), Direction::Inbound, &REQUEST);
    let file = minimal(&[epb.clone(), epb].concat());
    for cut in [file.len() - 1, file.len() - 57, file.len() - 52] {
        let mut r = Reader::new(&file[..cut]);
        assert!(r.next_packet().unwrap().is_some(), "cut at {cut}");
        match r.next_packet() {
            Err(ReadError::Truncated { offset: 128 }) => {}
            other => panic!("cut at {cut}: {other:?}"),
        }
    }
    let mut r = Reader::new(&file[..]);
    assert!(r.next_packet().unwrap().is_some());
    assert!(r.next_packet().unwrap().is_some());
    assert!(r.next_packet().unwrap().is_none());
    // Cut in the Section Header Block's magic.
    let e = Reader::new(&file[..10]).next_packet().unwrap_err();
    assert_eq!(e.to_string(), "byte 0: the file ends inside a block");
}

/// Packets of an interface no block described are skipped and counted; a packet block longer than
/// MAX_BLOCK is read past and counted; a section starts its interfaces afresh.
#[test]
fn what_is_skipped_is_counted() {
    let mut blocks = Vec::new();
    enhanced_packet(&mut blocks, 1, t1(), Direction::Inbound, &[1]);
    let big = vec![0u8; MAX_BLOCK as usize];
    enhanced_packet(&mut blocks, 0, t1(), Direction::Inbound, &big);
    enhanced_packet(&mut blocks, 0, t1(), Direction::Inbound, &[2]);
    section_header(&mut blocks, "");
    enhanced_packet(&mut blocks, 0, t1(), Direction::Inbound, &[3]);
    interface_description(&mut blocks, LINKTYPE_ETHERNET, "eth1");
    enhanced_packet(&mut blocks, 0, t1(), Direction::Inbound, &[4]);
    let file = minimal(&blocks);
    let mut r = Reader::new(&file[..]);
    let mut got = Vec::new();
    while let Some(p) = r.next_packet().unwrap() {
        got.push((p.link_type, p.data.to_vec()));
    }
    assert_eq!(got, [(227, vec![2]), (1, vec![4])]);
    assert_eq!((r.unknown_interface(), r.skipped()), (2, 1));
    assert_eq!(r.interfaces_seen().len(), 2);
    // Cut inside the long block.
    let cut = &file[..file.len() / 2];
    assert!(matches!(
        Reader::new(cut).next_packet(),
        Err(ReadError::Truncated { offset: 116 })
    ));
}

/// A section keeps MAX_INTERFACES interfaces; the packets of the next one are of an unknown
/// interface.
#[test]
fn interfaces_are_bounded() {
    let mut blocks = Vec::new();
    for _ in 0..MAX_INTERFACES {
        interface_description(&mut blocks, LINKTYPE_ETHERNET, "x");
    }
    enhanced_packet(
        &mut blocks,
        MAX_INTERFACES as u32,
        t1(),
        Direction::Inbound,
        &[1],
    );
    enhanced_packet(
        &mut blocks,
        MAX_INTERFACES as u32 - 1,
        t1(),
        Direction::Inbound,
        &[2],
    );
    let file = minimal(&blocks);
    let mut r = Reader::new(&file[..]);
    let p = r.next_packet().unwrap().unwrap();
    assert_eq!((p.link_type, p.data), (1, &[2][..]));
    assert_eq!(r.unknown_interface(), 1);
    assert_eq!(r.interfaces_seen().len(), MAX_INTERFACES);
    // A name is cut at 256 bytes.
    let mut long = Vec::new();
    interface_description(&mut long, 1, &"n".repeat(300));
    let mut file = Vec::new();
    section_header(&mut file, "");
    file.extend_from_slice(&long);
    let mut r = Reader::new(&file[..]);
    assert!(r.next_packet().unwrap().is_none());
    assert_eq!(
        r.interfaces_seen()[0].name.as_deref().map(str::len),
        Some(256)
    );
}

/// A block written into a buffer that holds something already is padded from its own start: the
/// same bytes after the one before it.
#[test]
fn blocks_are_padded_from_their_own_start() {
    for prefix in [1usize, 2, 3] {
        let (mut plain, mut after) = (Vec::new(), vec![0xEE; prefix]);
        enhanced_packet(&mut plain, 0, t1(), Direction::Inbound, &[1, 2, 3]);
        enhanced_packet(&mut after, 0, t1(), Direction::Inbound, &[1, 2, 3]);
        assert_eq!(after[prefix..], plain[..], "after {prefix} bytes");
        let (mut plain, mut after) = (Vec::new(), vec![0xEE; prefix]);
        interface_description(&mut plain, LINKTYPE_ETHERNET, "eth");
        interface_description(&mut after, LINKTYPE_ETHERNET, "eth");
        assert_eq!(after[prefix..], plain[..], "after {prefix} bytes");
    }
}

/// Each kind of block shorter than its fixed part is refused: a section of 24 bytes, an interface
/// of 16, an obsolete Packet Block of 28, a Simple Packet Block of 12.
#[test]
fn blocks_shorter_than_their_kind_are_refused() {
    let mut shb = Vec::new();
    section_header(&mut shb, "");
    let mut short_shb = shb.clone();
    short_shb[4] = 24;
    short_shb.truncate(24);
    short_shb[20..24].copy_from_slice(&[24, 0, 0, 0]);
    assert_eq!(
        error(&short_shb),
        "byte 0: block length 24 is not a length of a block of type 0x0A0D0D0A"
    );
    for (block_type, length) in [(1u8, 16u8), (2, 28), (3, 12)] {
        let mut file = minimal(&[]);
        let mut block = vec![0u8; usize::from(length)];
        block[0] = block_type;
        block[4] = length;
        let n = block.len();
        block[n - 4] = length;
        file.extend_from_slice(&block);
        assert_eq!(
            error(&file),
            format!(
                "byte 68: block length {length} is not a length of a block of type 0x{block_type:08X}"
            )
        );
    }
}

/// A block of exactly MAX_BLOCK bytes is read; a broken block after a longer one that was read
/// past is named at its own offset.
#[test]
fn the_longest_block_held_and_offsets_after_one_read_past() {
    let mut epb = Vec::new();
    // 32 bytes of block around the data: MAX_BLOCK - 32 bytes of data, no options.
    let data = vec![7u8; MAX_BLOCK as usize - 32];
    epb.extend_from_slice(&6u32.to_le_bytes());
    epb.extend_from_slice(&MAX_BLOCK.to_le_bytes());
    epb.extend_from_slice(&[0; 12]);
    epb.extend_from_slice(&(data.len() as u32).to_le_bytes());
    epb.extend_from_slice(&(data.len() as u32).to_le_bytes());
    epb.extend_from_slice(&data);
    epb.extend_from_slice(&MAX_BLOCK.to_le_bytes());
    let file = minimal(&epb);
    let mut r = Reader::new(&file[..]);
    assert_eq!(r.next_packet().unwrap().unwrap().data.len(), data.len());
    assert_eq!(r.skipped(), 0);
    let mut longer = Vec::new();
    enhanced_packet(
        &mut longer,
        0,
        t1(),
        Direction::Inbound,
        &[0; MAX_BLOCK as usize],
    );
    let after = 68 + longer.len();
    longer.extend_from_slice(&[6, 0, 0, 0, 33, 0, 0, 0]);
    assert_eq!(
        error(&minimal(&longer)),
        format!("byte {after}: block length 33 is not a length of a block of type 0x00000006")
    );
}

/// Options as other writers may leave them: if_tsresol and if_tsoffset of another length than
/// theirs are not taken; an option list without opt_endofopt ends at the block's end; an option of
/// another code is no epb_flags, and epb_flags of another length is none.
#[test]
fn options_other_writers_leave() {
    let mut file = Vec::new();
    section_header(&mut file, "");
    #[rustfmt::skip]
    file.extend_from_slice(&[
        // IDB, 44 bytes: if_tsresol of 2 bytes, if_tsoffset of 4, if_name "eth0", no end.
        1, 0, 0, 0, 44, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0,
        9, 0, 2, 0, 9, 0, 0, 0,
        14, 0, 4, 0, 1, 0, 0, 0,
        2, 0, 4, 0, b'e', b't', b'h', b'0',
        44, 0, 0, 0,
    ]);
    // EPB with 4 bytes and no options at all (the data fills the block).
    #[rustfmt::skip]
    file.extend_from_slice(&[
        6, 0, 0, 0, 36, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x40, 0x42, 0x0F, 0,
        4, 0, 0, 0, 4, 0, 0, 0, 1, 2, 3, 4, 36, 0, 0, 0,
    ]);
    // EPB with an option of code 3 (a hash) of 4 bytes, then epb_flags of 2 bytes.
    #[rustfmt::skip]
    file.extend_from_slice(&[
        6, 0, 0, 0, 52, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        4, 0, 0, 0, 4, 0, 0, 0, 5, 6, 7, 8,
        3, 0, 4, 0, 1, 0, 0, 0,
        2, 0, 2, 0, 1, 0, 0, 0,
        52, 0, 0, 0,
    ]);
    let mut r = Reader::new(&file[..]);
    let p = r.next_packet().unwrap().unwrap();
    // Microseconds (if_tsresol not taken), no offset: 1,000,000 µs.
    assert_eq!(p.time, Some(UNIX_EPOCH + Duration::from_secs(1)));
    assert_eq!((p.data, p.direction), (&[1, 2, 3, 4][..], None));
    let p = r.next_packet().unwrap().unwrap();
    assert_eq!((p.data, p.direction), (&[5, 6, 7, 8][..], None));
    let info = &r.interfaces_seen()[0];
    assert_eq!((info.tsresol, info.tsoffset), (6, 0));
    assert_eq!(info.name.as_deref(), Some("eth0"));
}

/// The obsolete Packet Block's interface is 16 bits, followed by its drops count.
#[test]
fn a_packet_block_with_drops() {
    #[rustfmt::skip]
    let pb = [
        2, 0, 0, 0, 36, 0, 0, 0, 0, 0, 5, 0, 0, 0, 0, 0, 1, 0, 0, 0,
        2, 0, 0, 0, 2, 0, 0, 0, 0xAB, 0xCD, 0, 0, 36, 0, 0, 0,
    ];
    let file = minimal(&pb);
    let mut r = Reader::new(&file[..]);
    let p = r.next_packet().unwrap().unwrap();
    assert_eq!((p.interface, p.data), (0, &[0xAB, 0xCD][..]));
    assert_eq!(p.time, Some(UNIX_EPOCH + Duration::from_nanos(1)));
    assert_eq!(r.unknown_interface(), 0);
}

/// A reader that is interrupted is read on; one that fails is an error.
#[test]
fn interrupted_and_failing_readers() {
    struct Interrupting<'a>(&'a [u8], bool);
    impl std::io::Read for Interrupting<'_> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            self.1 = !self.1;
            if self.1 {
                return Err(std::io::ErrorKind::Interrupted.into());
            }
            let n = buf.len().min(self.0.len()).min(5);
            buf[..n].copy_from_slice(&self.0[..n]);
            self.0 = &self.0[n..];
            Ok(n)
        }
    }
    let mut epb = Vec::new();
    enhanced_packet(&mut epb, 0, t1(), Direction::Inbound, &REQUEST);
    let file = minimal(&epb);
    let mut r = Reader::new(Interrupting(&file, false));
    assert_eq!(r.next_packet().unwrap().unwrap().data, REQUEST);
    struct Failing;
    impl std::io::Read for Failing {
        fn read(&mut self, _: &mut [u8]) -> std::io::Result<usize> {
            Err(std::io::Error::other("gone"))
        }
    }
    assert_eq!(
        Reader::new(Failing).next_packet().unwrap_err().to_string(),
        "gone"
    );
}
