//! The [`ObjectStore`] a CoE server hands the SDO server: the [`Dictionary`] with the EtherCAT rules of
//! ETG.1000.6 put between the wire and the values, either entry by entry or, for a complete access
//! (§5.6.2.1.2, §5.6.2.4.2), the whole object packed by [`crate::coe::complete`].
//!
//! The EtherCAT rules, checked before any data is buffered and again before anything is written:
//!
//! - **0x06010006** (object mapped to an RxPDO, SDO download blocked): a download to an entry the host
//!   marked as mapped to an RxPDO while the slave is in SafeOp or Op.
//! - **0x06010003** (sub-index 0 must be 0 for write access): a download to an entry ≥ 1 of a PDO mapping
//!   object (0x1600–0x17FF, 0x1A00–0x1BFF) or a PDO assignment object (0x1C12, 0x1C13) while its
//!   sub-index 0 is not 0 (the PDO configuration procedure of ETG.1000.6: write 0 to sub-index 0, then
//!   the entries, then the number of entries).

use std::collections::HashSet;

use crate::abort::AbortCode;
use crate::coe::complete;
use crate::dict::Dictionary;
use crate::hook::Bound;
use crate::sdo::frame::Address;
use crate::sdo::store::{DownloadCapacity, ObjectStore};

/// The dictionary as a CoE SDO server reads and writes it.
pub(super) struct CoeStore<'a, 'b> {
    objects: &'a mut Bound<'b>,
    rxpdo: &'a HashSet<Address>,
    /// Complete access: the multiplexer names the object and the first sub-index (0 or 1).
    complete: bool,
}

impl<'a, 'b> CoeStore<'a, 'b> {
    /// The store of one transfer: entry by entry, or the whole object when `complete`.
    pub(super) fn new(
        objects: &'a mut Bound<'b>,
        rxpdo: &'a HashSet<Address>,
        complete: bool,
    ) -> CoeStore<'a, 'b> {
        CoeStore {
            objects,
            rxpdo,
            complete,
        }
    }

    /// The EtherCAT rules for a download to `mux` (the object from `mux.sub` on, under complete access).
    fn check_download(&self, mux: Address) -> Result<(), AbortCode> {
        let blocked = if self.complete {
            self.rxpdo
                .iter()
                .any(|m| m.index == mux.index && m.sub >= mux.sub)
        } else {
            self.rxpdo.contains(&mux)
        };
        if blocked {
            return Err(AbortCode::MappedToRxPdo);
        }
        if mux.sub >= 1 && is_pdo_configuration(mux.index) {
            let count = self
                .objects
                .dict
                .entry(mux.index, 0)
                .ok()
                .and_then(|e| e.value.first().copied())
                .unwrap_or(0);
            if count != 0 {
                return Err(AbortCode::SubIndex0MustBeZero);
            }
        }
        Ok(())
    }
}

/// True for the PDO mapping objects (0x1600–0x17FF RxPDO, 0x1A00–0x1BFF TxPDO) and the sync manager PDO
/// assignment objects of the process data sync managers (0x1C12 outputs, 0x1C13 inputs).
pub fn is_pdo_configuration(index: u16) -> bool {
    matches!(index, 0x1600..=0x17FF | 0x1A00..=0x1BFF | 0x1C12 | 0x1C13)
}

/// The most bytes a complete download of object `mux.index` from `mux.sub` (0 or 1) takes: every entry
/// up to the highest sub-index present, sub-index 0 as 16 bits. Refused when the object does not exist
/// (0x06020000), is not an ARRAY or RECORD or has an entry of variable length (0x06010004), or has no
/// entry that may be written (0x06010002).
fn complete_capacity(d: &Dictionary, mux: Address) -> Result<DownloadCapacity, AbortCode> {
    let object = d.object(mux.index).ok_or(AbortCode::NoObject)?;
    if !object.kind.has_subs() {
        return Err(AbortCode::CompleteAccessUnsupported);
    }
    let from_sub0 = mux.sub == 0;
    let mut bits: u64 = if from_sub0 { 16 } else { 0 };
    let mut writable = from_sub0 && object.sub(0).is_some_and(|e| e.access.kind.writable());
    for entry in object.subs.range(1..).map(|(_, e)| e) {
        let size = entry
            .data_type
            .bit_size()
            .ok_or(AbortCode::CompleteAccessUnsupported)?;
        bits += u64::from(size);
        writable |= entry.access.kind.writable();
    }
    if !writable {
        return Err(AbortCode::ReadOnly);
    }
    Ok(DownloadCapacity::UpTo(bits.div_ceil(8) as usize))
}

impl ObjectStore for CoeStore<'_, '_> {
    fn upload(&mut self, mux: Address) -> Result<Vec<u8>, AbortCode> {
        let o = &mut *self.objects;
        if self.complete {
            complete::upload_through(o.dict, o.hook, mux.index, mux.sub == 0)
        } else {
            o.upload(mux)
        }
    }

    fn download_capacity(&self, mux: Address) -> Result<DownloadCapacity, AbortCode> {
        let capacity = if self.complete {
            complete_capacity(self.objects.dict, mux)?
        } else {
            self.objects.download_capacity(mux)?
        };
        self.check_download(mux)?;
        Ok(capacity)
    }

    fn download(&mut self, mux: Address, data: &[u8]) -> Result<(), AbortCode> {
        self.check_download(mux)?;
        let o = &mut *self.objects;
        if self.complete {
            complete::download_through(o.dict, o.hook, o.now, mux.index, mux.sub == 0, data)
        } else {
            o.download(mux, data)
        }
    }
}

/// A store for feeding the SDO server a frame that reads and writes nothing (an abort that ends its
/// transfer): every access is refused.
pub(super) struct Detached;

impl ObjectStore for Detached {
    fn upload(&mut self, _: Address) -> Result<Vec<u8>, AbortCode> {
        Err(AbortCode::General)
    }

    fn download_capacity(&self, _: Address) -> Result<DownloadCapacity, AbortCode> {
        Err(AbortCode::General)
    }

    fn download(&mut self, _: Address, _: &[u8]) -> Result<(), AbortCode> {
        Err(AbortCode::General)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::{AccessType, Object, ObjectKind, SubObject};
    use crate::types::DataType;
    use crate::value::Value;

    fn dict() -> Dictionary {
        let mut d = Dictionary::new();
        d.insert(
            Object::structured(0x1600, "RxPDO 1 mapping", ObjectKind::Record)
                .with_sub(
                    0,
                    SubObject::new("n", DataType::Unsigned8, AccessType::Rw)
                        .with_default(Value::Uint(1)),
                )
                .with_sub(
                    1,
                    SubObject::new("1", DataType::Unsigned32, AccessType::Rw)
                        .with_default(Value::Uint(0x7000_0110)),
                )
                .with_sub(2, SubObject::new("2", DataType::Unsigned32, AccessType::Rw)),
        );
        d.insert(
            Object::structured(0x6000, "Inputs", ObjectKind::Record)
                .with_sub(
                    0,
                    SubObject::new("n", DataType::Unsigned8, AccessType::Ro)
                        .with_default(Value::Uint(1)),
                )
                .with_sub(1, SubObject::new("a", DataType::Unsigned16, AccessType::Ro)),
        );
        d.insert(
            Object::structured(0x2000, "Names", ObjectKind::Array)
                .with_sub(
                    0,
                    SubObject::new("n", DataType::Unsigned8, AccessType::Ro)
                        .with_default(Value::Uint(1)),
                )
                .with_sub(
                    1,
                    SubObject::new("1", DataType::VisibleString, AccessType::Rw).with_bit_size(64),
                ),
        );
        d
    }

    #[test]
    fn pdo_configuration_objects() {
        for index in [0x1600, 0x17FF, 0x1A00, 0x1BFF, 0x1C12, 0x1C13] {
            assert!(is_pdo_configuration(index), "{index:04X}");
        }
        for index in [0x15FF, 0x1800, 0x19FF, 0x1C00, 0x1C11, 0x1C14, 0x7000] {
            assert!(!is_pdo_configuration(index), "{index:04X}");
        }
    }

    #[test]
    fn sub_index_0_must_be_0_for_writing_entries() {
        let mut d = dict();
        let none = HashSet::new();
        let mut hook = crate::hook::NoHook;
        let mut bound = Bound::new(&mut d, &mut hook, std::time::Instant::now());
        let mut store = CoeStore::new(&mut bound, &none, false);
        assert_eq!(
            store.download_capacity(Address::new(0x1600, 2)),
            Err(AbortCode::SubIndex0MustBeZero)
        );
        assert_eq!(
            store.download(Address::new(0x1600, 2), &[0x10, 0x02, 0x00, 0x70]),
            Err(AbortCode::SubIndex0MustBeZero)
        );
        // Sub-index 0 itself may be written; once it is 0 the entries may be too.
        assert_eq!(store.download(Address::new(0x1600, 0), &[0]), Ok(()));
        assert_eq!(
            store.download(Address::new(0x1600, 2), &[0x10, 0x02, 0x00, 0x70]),
            Ok(())
        );
        assert_eq!(d.read(0x1600, 2).unwrap(), &[0x10, 0x02, 0x00, 0x70]);
    }

    #[test]
    fn rxpdo_mapped_entries_refuse_downloads() {
        let mut d = dict();
        d.write(0x1600, 0, &[0]).unwrap();
        let mapped: HashSet<_> = [Address::new(0x1600, 1)].into();
        let mut hook = crate::hook::NoHook;
        let mut bound = Bound::new(&mut d, &mut hook, std::time::Instant::now());
        let store = CoeStore::new(&mut bound, &mapped, false);
        assert_eq!(
            store.download_capacity(Address::new(0x1600, 1)),
            Err(AbortCode::MappedToRxPdo)
        );
        assert_eq!(
            store.download_capacity(Address::new(0x1600, 2)),
            Ok(DownloadCapacity::Fixed(4))
        );
        let store = CoeStore::new(&mut bound, &mapped, true);
        assert_eq!(
            store.download_capacity(Address::new(0x1600, 0)),
            Err(AbortCode::MappedToRxPdo)
        );
    }

    #[test]
    fn complete_capacities() {
        let mut d = dict();
        let none = HashSet::new();
        let mut hook = crate::hook::NoHook;
        let mut bound = Bound::new(&mut d, &mut hook, std::time::Instant::now());
        let store = CoeStore::new(&mut bound, &none, true);
        // Sub-index 0 as 16 bits and two UNSIGNED32.
        assert_eq!(
            store.download_capacity(Address::new(0x1600, 0)),
            Ok(DownloadCapacity::UpTo(10))
        );
        assert_eq!(
            store.download_capacity(Address::new(0x6000, 0)),
            Err(AbortCode::ReadOnly)
        );
        assert_eq!(
            store.download_capacity(Address::new(0x2000, 1)),
            Err(AbortCode::CompleteAccessUnsupported)
        );
        assert_eq!(
            store.download_capacity(Address::new(0x3000, 0)),
            Err(AbortCode::NoObject)
        );
        // From sub-index 1 the rule of sub-index 0 applies as to a single entry.
        assert_eq!(
            store.download_capacity(Address::new(0x1600, 1)),
            Err(AbortCode::SubIndex0MustBeZero)
        );
    }
}
