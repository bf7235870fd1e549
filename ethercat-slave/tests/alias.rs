//! The configured station alias: written into the SII through the EEPROM interface (as configuration
//! tools set it), loaded into 0x0012 by a reload, and an address for configured-address datagrams once
//! the master enables alias addressing (DL control 0x0100 bit 24).

mod common;

use common::master::*;
use ethercat_slave::esc::cmd;
use ethercat_slave::master::SimChain;
use ethercat_slave::smd::binding::Device;

#[test]
fn alias_from_the_sii_addresses_the_unit_when_enabled() {
    let mut c = SimChain::new(Device::Smd23kB, 2).unwrap();
    configure(&mut c);
    assert_eq!(
        fprd(&mut c, 1, 0x0012, 2).0,
        [0, 0],
        "no alias in the generated SII"
    );
    // A write without write enable is refused (error bit 13), nothing changes.
    fpwr(&mut c, 1, 0x0508, vec![0x77, 0x07]);
    fpwr(&mut c, 1, 0x0502, vec![0x00, 0x02, 4, 0, 0, 0]);
    assert_eq!(fprd(&mut c, 1, 0x0502, 2).0, [0x40, 0x20]);
    // Word 4 = 0x0777 with write enable, then a reload.
    fpwr(&mut c, 1, 0x0502, vec![0x01, 0x02, 4, 0, 0, 0]);
    assert_eq!(fprd(&mut c, 1, 0x0502, 2).0, [0x40, 0x00], "done, no error");
    fpwr(&mut c, 1, 0x0502, vec![0x00, 0x04]);
    assert_eq!(fprd(&mut c, 1, 0x0012, 2).0, [0x77, 0x07]);
    // The master cannot write the alias register itself.
    fpwr(&mut c, 1, 0x0012, vec![0x55, 0x05]);
    assert_eq!(fprd(&mut c, 1, 0x0012, 2).0, [0x77, 0x07]);
    // The SII reads the new word back.
    fpwr(&mut c, 1, 0x0502, vec![0x00, 0x01, 4, 0, 0, 0]);
    assert_eq!(fprd(&mut c, 1, 0x0508, 2).0, [0x77, 0x07]);
    // Alias addressing off: nobody answers 0x0777; on: unit 1 does.
    assert_eq!(reg(&mut c, cmd::FPRD, 0x0777, 0x0130, vec![0; 2]).wkc, 0);
    fpwr(&mut c, 1, 0x0103, vec![0x01]);
    let r = reg(&mut c, cmd::FPRD, 0x0777, 0x0010, vec![0; 2]);
    assert_eq!((r.wkc, r.data), (1, station(1).to_le_bytes().to_vec()));
    // Its station address still works.
    assert_eq!(fprd(&mut c, 1, 0x0130, 2), (vec![1, 0], 1));
}
