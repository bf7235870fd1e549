#![no_main]
//! Whatever a reader accepts, its writer writes, the reader reads back, and writing that again gives the
//! same text: the first byte picks the format (ESI, XDD, EDS), the rest is the file.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Some((&pick, file)) = data.split_first() else {
        return;
    };
    match pick % 3 {
        0 => {
            if let Ok(devs) = od::esi::read_all(file, "fuzz") {
                if devs.is_empty() {
                    return;
                }
                let text = od::esi::write_all(&devs);
                let back =
                    od::esi::read_all(text.as_bytes(), "written").expect("written ESI reads");
                assert_eq!(od::esi::write_all(&back), text);
            }
        }
        1 => {
            if let Ok(dev) = od::xdd::read(file, "fuzz") {
                let text = od::xdd::write(&dev);
                let back = od::xdd::read(text.as_bytes(), "written").expect("written XDD reads");
                assert_eq!(od::xdd::write(&back), text);
            }
        }
        _ => {
            if let Ok(dev) = od::eds::read(file, "fuzz") {
                let text = od::eds::write_eds(&dev);
                let back = od::eds::read(text.as_bytes(), "written").expect("written EDS reads");
                assert_eq!(od::eds::write_eds(&back), text);
                let dcf = od::eds::write_dcf(&dev);
                let back = od::eds::read(dcf.as_bytes(), "written").expect("written DCF reads");
                assert_eq!(od::eds::write_dcf(&back), dcf);
            }
        }
    }
});
