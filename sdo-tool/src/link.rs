//! What the tool takes from the links and the dictionary crate: the CAN side (`can-link`: frames
//! and buses), the EtherCAT side (`ecat-link`: the raw socket), their captures (`link-capture`)
//! and the CiA 301 constants and codes it decodes (`od`). The rest of the tool names these through this module only; the tool
//! depends on no node and no emulator.

pub use can_link::transport::open as open_spec;
pub use can_link::transport::Captured;
pub use can_link::transport::{
    BusError, BusEvent, BusSpec, CanBus, SocketCanBus, SocketcandClient, BUS_VARIABLE,
    SOCKETCAND_DEFAULT_PORT,
};
pub use can_link::{CanFrame, NotClassic};
pub use ecat_link::raw::RawSocket;
pub use link_capture::{pcapng, Capture, CaptureError};
pub use od::emcy::EmcyCode;
pub use od::pdo::{PdoConfig, RPDO_COMM, TPDO_COMM};
pub use od::sdo::{LOAD_SIGNATURE, SAVE_SIGNATURE};
