//! The concise DCF (CiA 302-3 §4.2, the value of object 0x1F22): a little-endian UNSIGNED32 count of
//! entries, then per entry the index (UNSIGNED16), the sub-index (UNSIGNED8), the size of the data in
//! bytes (UNSIGNED32) and the data.
//!
//! The size is what the entry says: [`encode`] writes what it is given, so an entry whose data is
//! longer than its size (dcfgen writes INTEGER24 values with size 3 and four bytes of data) is kept as
//! it was made. [`decode`] reads `size` bytes of data, as a CANopen manager does.

use thiserror::Error;

/// One entry: the value to write to `index:sub`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Entry {
    /// Object index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// The size field: the number of bytes the value has.
    pub size: u32,
    /// The bytes written after the size field.
    pub data: Vec<u8>,
}

impl Entry {
    /// An entry whose size is the length of `data`.
    pub fn new(index: u16, sub: u8, data: Vec<u8>) -> Entry {
        Entry {
            index,
            sub,
            size: data.len() as u32,
            data,
        }
    }

    /// Appends the entry's bytes (header and data) to `out`.
    pub fn emit(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.index.to_le_bytes());
        out.push(self.sub);
        out.extend_from_slice(&self.size.to_le_bytes());
        out.extend_from_slice(&self.data);
    }
}

/// Why bytes are no concise DCF.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ConciseError {
    /// The bytes end inside the count, a header or the data of an entry.
    #[error("the concise DCF ends at byte {at} inside entry {entry} of {count}")]
    Truncated {
        /// The byte offset where the data ran out.
        at: usize,
        /// The entry, from 1 (0: the count itself).
        entry: u32,
        /// The number of entries the count gives.
        count: u32,
    },
    /// Bytes follow the last entry.
    #[error("{extra} bytes follow the last of {count} entries of the concise DCF")]
    Trailing {
        /// How many bytes follow.
        extra: usize,
        /// The number of entries.
        count: u32,
    },
}

/// The concise DCF of `entries`.
pub fn encode(entries: &[Entry]) -> Vec<u8> {
    let mut out = Vec::with_capacity(4 + entries.iter().map(|e| 7 + e.data.len()).sum::<usize>());
    out.extend_from_slice(&(entries.len() as u32).to_le_bytes());
    for entry in entries {
        entry.emit(&mut out);
    }
    out
}

/// The entries of a concise DCF, each with `size` bytes of data.
pub fn decode(bytes: &[u8]) -> Result<Vec<Entry>, ConciseError> {
    let take = |at: usize, n: usize| bytes.get(at..at.checked_add(n)?).map(|b| (b, at + n));
    let truncated = |entry, count| ConciseError::Truncated {
        at: bytes.len(),
        entry,
        count,
    };
    let (head, mut at) = take(0, 4).ok_or(truncated(0, 0))?;
    let count = u32::from_le_bytes([head[0], head[1], head[2], head[3]]);
    let mut entries = Vec::new();
    for n in 1..=count {
        let (h, next) = take(at, 7).ok_or(truncated(n, count))?;
        let size = u32::from_le_bytes([h[3], h[4], h[5], h[6]]);
        let (data, next) = take(next, size as usize).ok_or(truncated(n, count))?;
        entries.push(Entry {
            index: u16::from_le_bytes([h[0], h[1]]),
            sub: h[2],
            size,
            data: data.to_vec(),
        });
        at = next;
    }
    if at != bytes.len() {
        return Err(ConciseError::Trailing {
            extra: bytes.len() - at,
            count,
        });
    }
    Ok(entries)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Two entries worked out by hand: 0x1017:00 = 1000 ms (UNSIGNED16) and 0x1800:01 = 0x80000185.
    const TWO: [u8; 4 + 9 + 11] = [
        0x02, 0x00, 0x00, 0x00, // two entries
        0x17, 0x10, 0x00, 0x02, 0x00, 0x00, 0x00, 0xE8, 0x03, // 0x1017:00, 2 bytes, 1000
        0x00, 0x18, 0x01, 0x04, 0x00, 0x00, 0x00, 0x85, 0x01, 0x00,
        0x80, // 0x1800:01, 4 bytes
    ];

    fn two() -> Vec<Entry> {
        vec![
            Entry::new(0x1017, 0, vec![0xE8, 0x03]),
            Entry::new(0x1800, 1, 0x8000_0185u32.to_le_bytes().to_vec()),
        ]
    }

    #[test]
    fn encode_writes_count_then_index_sub_size_data() {
        assert_eq!(encode(&two()), TWO);
    }

    #[test]
    fn decode_reads_what_encode_wrote() {
        assert_eq!(decode(&TWO).unwrap(), two());
    }

    #[test]
    fn no_entries_is_a_zero_count() {
        assert_eq!(encode(&[]), [0, 0, 0, 0]);
        assert_eq!(decode(&[0, 0, 0, 0]).unwrap(), vec![]);
    }

    #[test]
    fn a_size_shorter_than_the_data_is_kept() {
        // INTEGER24 -2 as dcfgen writes it: size 3, four bytes.
        let e = Entry {
            index: 0x2000,
            sub: 1,
            size: 3,
            data: vec![0xFE, 0xFF, 0xFF, 0xFF],
        };
        let mut out = Vec::new();
        e.emit(&mut out);
        assert_eq!(
            out,
            [0x00, 0x20, 0x01, 0x03, 0, 0, 0, 0xFE, 0xFF, 0xFF, 0xFF]
        );
    }

    #[test]
    fn truncated_and_trailing_bytes_are_refused() {
        assert_eq!(
            decode(&TWO[..TWO.len() - 1]),
            Err(ConciseError::Truncated {
                at: 23,
                entry: 2,
                count: 2
            })
        );
        assert_eq!(
            decode(&[1, 0]),
            Err(ConciseError::Truncated {
                at: 2,
                entry: 0,
                count: 0
            })
        );
        let mut long = TWO.to_vec();
        long.push(0);
        assert_eq!(
            decode(&long),
            Err(ConciseError::Trailing { extra: 1, count: 2 })
        );
        assert!(decode(&[0xFF, 0xFF, 0xFF, 0xFF, 0, 0]).is_err());
    }

    proptest! {
        #[test]
        fn round_trip(entries in proptest::collection::vec(
            (any::<u16>(), any::<u8>(), proptest::collection::vec(any::<u8>(), 0..12)), 0..16)) {
            let entries: Vec<Entry> =
                entries.into_iter().map(|(i, s, d)| Entry::new(i, s, d)).collect();
            prop_assert_eq!(decode(&encode(&entries)).unwrap(), entries);
        }

        #[test]
        fn any_bytes_decode_or_fail_without_panic(bytes in proptest::collection::vec(any::<u8>(), 0..64)) {
            let _ = decode(&bytes);
        }
    }
}
