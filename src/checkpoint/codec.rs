//! The checkpoint file's little-endian primitives: numbers, strings and
//! arrays written and read back with their lengths, and the checksum.

use glam::DVec2;

/// 64-bit FNV-1a: enough to tell a damaged file from an intact one.
pub(super) fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

pub(super) struct Writer(pub(super) Vec<u8>);

impl Writer {
    pub(super) fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    pub(super) fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }
    pub(super) fn bytes(&mut self, b: &[u8]) {
        self.u64(b.len() as u64);
        self.0.extend_from_slice(b);
    }
    pub(super) fn str(&mut self, s: &str) {
        self.bytes(s.as_bytes());
    }
    pub(super) fn f64s(&mut self, v: &[f64]) {
        self.u64(v.len() as u64);
        for x in v {
            self.f64(*x);
        }
    }
    /// Records of four values (a tensor's components), as one list of
    /// their values.
    pub(super) fn quads(&mut self, v: impl ExactSizeIterator<Item = [f64; 4]>) {
        self.u64(4 * v.len() as u64);
        for q in v {
            q.iter().for_each(|x| self.f64(*x));
        }
    }
    pub(super) fn vec2s(&mut self, v: &[DVec2]) {
        self.u64(v.len() as u64);
        for p in v {
            self.f64(p.x);
            self.f64(p.y);
        }
    }
    pub(super) fn u32s(&mut self, v: &[u32]) {
        self.u64(v.len() as u64);
        for x in v {
            self.0.extend_from_slice(&x.to_le_bytes());
        }
    }
}

/// Bounds-checked reads: a count larger than what is left is an error, not
/// an allocation.
pub(super) struct Reader<'a> {
    pub(super) b: &'a [u8],
    pub(super) at: usize,
}

impl Reader<'_> {
    pub(super) fn take(&mut self, n: usize) -> Result<&[u8], String> {
        if n > self.b.len() - self.at {
            return Err("the checkpoint ends early".into());
        }
        let s = &self.b[self.at..self.at + n];
        self.at += n;
        Ok(s)
    }
    pub(super) fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().expect("8")))
    }
    pub(super) fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_bits(self.u64()?))
    }
    /// A count of items of at least `item` bytes each.
    pub(super) fn count(&mut self, item: usize) -> Result<usize, String> {
        let k = self.u64()?;
        if k > ((self.b.len() - self.at) / item) as u64 {
            return Err("the checkpoint ends early".into());
        }
        Ok(k as usize)
    }
    pub(super) fn bytes(&mut self) -> Result<&[u8], String> {
        let k = self.count(1)?;
        self.take(k)
    }
    pub(super) fn str(&mut self) -> Result<String, String> {
        String::from_utf8(self.bytes()?.to_vec()).map_err(|_| "a text is not UTF-8".into())
    }
    pub(super) fn f64s(&mut self) -> Result<Vec<f64>, String> {
        let k = self.count(8)?;
        (0..k).map(|_| self.f64()).collect()
    }
    pub(super) fn quads(&mut self) -> Result<Vec<[f64; 4]>, String> {
        let v = self.f64s()?;
        if v.len() % 4 != 0 {
            return Err(format!(
                "a list of {} values is not of four-value records",
                v.len()
            ));
        }
        Ok(v.chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect())
    }
    pub(super) fn vec2s(&mut self) -> Result<Vec<DVec2>, String> {
        let k = self.count(16)?;
        (0..k)
            .map(|_| Ok(DVec2::new(self.f64()?, self.f64()?)))
            .collect()
    }
    pub(super) fn u32s(&mut self) -> Result<Vec<u32>, String> {
        let k = self.count(4)?;
        Ok(self
            .take(4 * k)?
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes(c.try_into().expect("4")))
            .collect())
    }
}
