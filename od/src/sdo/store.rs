//! What an SDO server reads and writes: the [`ObjectStore`] trait, implemented for [`Dictionary`].
//!
//! The server never touches a dictionary directly, so a node can put its own rules between the wire and
//! the values (PDO mapping checks, values computed on read, an EtherCAT CoE server on the same objects)
//! by wrapping the dictionary in another store.

use crate::abort::AbortCode;
use crate::dict::Dictionary;
use crate::sdo::frame::Address;

/// How many bytes a download to an entry may bring (CiA 301 §7.2.4.3.3: the server refuses a download
/// that announces more than the entry holds before any data comes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DownloadCapacity {
    /// A fixed-size type: exactly this many bytes.
    Fixed(usize),
    /// A string or DOMAIN with a capacity: at most this many bytes.
    UpTo(usize),
    /// No bound from the entry (a DOMAIN without a size): the server's own limit applies.
    Unbounded,
}

/// The objects an SDO server serves.
///
/// Every method answers a refusal with the CiA 301 abort code the server sends (§7.2.4.3.17).
pub trait ObjectStore {
    /// The value of `mux` as an upload sends it; refused when the entry does not exist or is write-only.
    fn upload(&mut self, mux: Address) -> Result<Vec<u8>, AbortCode>;

    /// Whether `mux` may be downloaded to and how many bytes it takes, asked before any data is
    /// buffered: refused when the entry does not exist or is read-only or constant (0x06010002).
    fn download_capacity(&self, mux: Address) -> Result<DownloadCapacity, AbortCode>;

    /// Writes the whole value of a finished download, with every check (access, length, validity,
    /// limits). A refusal changes nothing.
    fn download(&mut self, mux: Address, data: &[u8]) -> Result<(), AbortCode>;
}

impl ObjectStore for Dictionary {
    fn upload(&mut self, mux: Address) -> Result<Vec<u8>, AbortCode> {
        self.read(mux.index, mux.sub)
            .map(<[u8]>::to_vec)
            .map_err(|e| e.abort_code())
    }

    fn download_capacity(&self, mux: Address) -> Result<DownloadCapacity, AbortCode> {
        let entry = self.entry(mux.index, mux.sub).map_err(|e| e.abort_code())?;
        if !entry.access.kind.writable() {
            return Err(AbortCode::ReadOnly);
        }
        Ok(match entry.data_type.byte_size() {
            Some(size) => DownloadCapacity::Fixed(size),
            None => match entry.capacity() {
                Some(cap) => DownloadCapacity::UpTo(cap),
                None => DownloadCapacity::Unbounded,
            },
        })
    }

    fn download(&mut self, mux: Address, data: &[u8]) -> Result<(), AbortCode> {
        self.write(mux.index, mux.sub, data)
            .map_err(|e| e.abort_code())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::{AccessType, Object, SubObject};
    use crate::types::DataType;
    use crate::value::Value;

    fn dict() -> Dictionary {
        let mut d = Dictionary::new();
        d.insert(Object::var(
            0x1000,
            SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro)
                .with_default(Value::Uint(0x0002_0192)),
        ));
        d.insert(Object::var(
            0x1017,
            SubObject::new("Heartbeat", DataType::Unsigned16, AccessType::Rw),
        ));
        d.insert(Object::var(
            0x2000,
            SubObject::new("Name", DataType::VisibleString, AccessType::Rw).with_bit_size(80),
        ));
        d.insert(Object::var(
            0x2001,
            SubObject::new("Blob", DataType::Domain, AccessType::Wo),
        ));
        d
    }

    #[test]
    fn capacities() {
        let d = dict();
        assert_eq!(
            d.download_capacity(Address::new(0x1017, 0)),
            Ok(DownloadCapacity::Fixed(2))
        );
        assert_eq!(
            d.download_capacity(Address::new(0x2000, 0)),
            Ok(DownloadCapacity::UpTo(10))
        );
        assert_eq!(
            d.download_capacity(Address::new(0x2001, 0)),
            Ok(DownloadCapacity::Unbounded)
        );
        assert_eq!(
            d.download_capacity(Address::new(0x1000, 0)),
            Err(AbortCode::ReadOnly)
        );
        assert_eq!(
            d.download_capacity(Address::new(0x3000, 0)),
            Err(AbortCode::NoObject)
        );
        assert_eq!(
            d.download_capacity(Address::new(0x1017, 1)),
            Err(AbortCode::NoSubIndex)
        );
    }

    #[test]
    fn upload_and_download_check_access() {
        let mut d = dict();
        assert_eq!(
            d.upload(Address::new(0x1000, 0)),
            Ok(vec![0x92, 0x01, 0x02, 0x00])
        );
        assert_eq!(d.upload(Address::new(0x2001, 0)), Err(AbortCode::WriteOnly));
        assert_eq!(
            d.download(Address::new(0x1000, 0), &[0, 0, 0, 0]),
            Err(AbortCode::ReadOnly)
        );
        assert_eq!(
            d.download(Address::new(0x1017, 0), &[1]),
            Err(AbortCode::LengthTooLow)
        );
        assert_eq!(d.download(Address::new(0x1017, 0), &[0xE8, 0x03]), Ok(()));
        assert_eq!(d.read(0x1017, 0).unwrap(), &[0xE8, 0x03]);
    }
}
