//! PDO configuration as the dictionary holds it: [`od::pdo`].

pub use od::pdo::*;
