//! CoE SDO mailboxes framed byte by byte as ETG.1000.6 lays them out, for the masters of the in-process
//! tests (`master.rs` for the SMD chain, `node.rs` for ethercat-node's units).

/// A CoE SDO request mailbox: header (length, address 0, channel 0, type 3 = CoE, `counter`), CoE
/// header (service 2, SDO request), the SDO bytes.
pub fn coe_request(counter: u8, sdo: &[u8]) -> Vec<u8> {
    let mut m = ((2 + sdo.len()) as u16).to_le_bytes().to_vec();
    m.extend_from_slice(&[0, 0, 0, 0x03 | (counter << 4)]);
    m.extend_from_slice(&[0x00, 0x20]);
    m.extend_from_slice(sdo);
    m
}

/// The SDO bytes of a CoE response mailbox (after the 6-byte mailbox and 2-byte CoE headers), or
/// the abort code when it is an abort.
pub fn coe_answer(m: &[u8]) -> Result<Vec<u8>, u32> {
    let len = usize::from(u16::from_le_bytes([m[0], m[1]]));
    assert_eq!(m[5] & 0x0F, 0x03, "a CoE mailbox");
    let sdo = m[8..6 + len].to_vec();
    let service = m[7] >> 4;
    if sdo[0] == 0x80 {
        assert_eq!(service, 2, "an abort is an SDO request");
        return Err(u32::from_le_bytes([sdo[4], sdo[5], sdo[6], sdo[7]]));
    }
    assert_eq!(service, 3, "an SDO response");
    Ok(sdo)
}
