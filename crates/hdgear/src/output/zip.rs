//! A ZIP archive of stored (uncompressed) entries: what an FMU is. Written in full, with fixed
//! dates (1980-01-01), so that the same entries give the same bytes.

/// The archive of `entries` (path inside the archive, bytes), in their order. Entries and the
/// archive stay below 4 GiB (no ZIP64): an error names the entry otherwise.
///
/// ```
/// let zip = hdgear::output::zip::stored(&[("a/b.txt", b"hello")]).unwrap();
/// assert_eq!(&zip[..4], b"PK\x03\x04");
/// assert_eq!(&zip[30..37], b"a/b.txt");
/// ```
pub fn stored(entries: &[(&str, &[u8])]) -> crate::error::Result<Vec<u8>> {
    let too_large = |name: &str| crate::error::Error::InvalidInput {
        what: "archive entry",
        text: name.to_string(),
        reason: "an entry and the archive must stay below 4 GiB".into(),
    };
    let mut out = Vec::new();
    let mut central = Vec::new();
    let date: u16 = 1 << 5 | 1; // 1980-01-01, 00:00
    for (name, data) in entries {
        let offset = u32::try_from(out.len()).map_err(|_| too_large(name))?;
        let size = u32::try_from(data.len()).map_err(|_| too_large(name))?;
        let name_len = u16::try_from(name.len()).map_err(|_| too_large(name))?;
        let crc = crc32fast::hash(data);
        // the fields a local header and a central record share, from "version needed" on
        let mut common = Vec::with_capacity(26);
        for v in [20u16, 0, 0, 0, date] {
            common.extend(v.to_le_bytes());
        }
        for v in [crc, size, size] {
            common.extend(v.to_le_bytes());
        }
        common.extend(name_len.to_le_bytes());
        common.extend(0u16.to_le_bytes()); // no extra field
        out.extend(0x0403_4b50u32.to_le_bytes());
        out.extend(&common);
        out.extend(name.as_bytes());
        out.extend(*data);
        central.extend(0x0201_4b50u32.to_le_bytes());
        central.extend(20u16.to_le_bytes()); // made by: version 2.0
        central.extend(&common);
        for v in [0u16, 0, 0] {
            central.extend(v.to_le_bytes()); // comment, disk, internal attributes
        }
        central.extend(0u32.to_le_bytes()); // external attributes
        central.extend(offset.to_le_bytes());
        central.extend(name.as_bytes());
    }
    let count = u16::try_from(entries.len()).map_err(|_| too_large("the entry list"))?;
    let at = u32::try_from(out.len()).map_err(|_| too_large("the archive"))?;
    let size = u32::try_from(central.len()).map_err(|_| too_large("the archive"))?;
    out.extend(central);
    out.extend(0x0605_4b50u32.to_le_bytes());
    for v in [0u16, 0, count, count] {
        out.extend(v.to_le_bytes());
    }
    out.extend(size.to_le_bytes());
    out.extend(at.to_le_bytes());
    out.extend(0u16.to_le_bytes());
    Ok(out)
}
