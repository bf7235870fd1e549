//! libFuzzer target for the ESI reader: any bytes must give a description list or a `ParseError`, never a
//! panic; what reads must also write and read again.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(devices) = od::esi::read_all(data, "fuzz") {
        let text = od::esi::write_all(&devices);
        let _ = od::esi::read_all(text.as_bytes(), "fuzz-written");
    }
});
