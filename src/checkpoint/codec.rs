//! The checkpoint file's little-endian primitives (numbers, strings and
//! arrays written and read back with their lengths), the checksum, and
//! [`Record`]: each kind of value the file holds, written and read in one
//! place.

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
    /// Records of four values (a tensor's components), as one list of
    /// their values.
    pub(super) fn quads(&mut self, v: impl ExactSizeIterator<Item = [f64; 4]>) {
        self.u64(4 * v.len() as u64);
        for q in v {
            q.iter().for_each(|x| self.f64(*x));
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
}

/// A value the checkpoint holds: how it is written and read back, in one
/// place, so the two cannot drift apart.
pub(super) trait Record: Sized {
    /// The fewest bytes one such value takes: a list's count is checked
    /// against what is left of the file before anything is allocated.
    const MIN: usize;
    fn put(&self, w: &mut Writer);
    fn get(r: &mut Reader) -> Result<Self, String>;
}

impl Record for u64 {
    const MIN: usize = 8;
    fn put(&self, w: &mut Writer) {
        w.u64(*self);
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        r.u64()
    }
}

impl Record for u32 {
    const MIN: usize = 4;
    fn put(&self, w: &mut Writer) {
        w.0.extend_from_slice(&self.to_le_bytes());
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        Ok(u32::from_le_bytes(r.take(4)?.try_into().expect("4")))
    }
}

impl Record for bool {
    const MIN: usize = 1;
    fn put(&self, w: &mut Writer) {
        w.0.push(u8::from(*self));
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        match r.take(1)?[0] {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(format!("a flag reads {b}, neither 0 nor 1")),
        }
    }
}

impl Record for f64 {
    const MIN: usize = 8;
    fn put(&self, w: &mut Writer) {
        w.f64(*self);
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        r.f64()
    }
}

impl Record for String {
    const MIN: usize = 8;
    fn put(&self, w: &mut Writer) {
        w.str(self);
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        r.str()
    }
}

impl Record for DVec2 {
    const MIN: usize = 16;
    fn put(&self, w: &mut Writer) {
        w.f64(self.x);
        w.f64(self.y);
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        Ok(DVec2::new(r.f64()?, r.f64()?))
    }
}

impl Record for crate::physics::support::Metric {
    const MIN: usize = 24;
    fn put(&self, w: &mut Writer) {
        w.f64(self.xx);
        w.f64(self.xy);
        w.f64(self.yy);
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        Ok(crate::physics::support::Metric {
            xx: r.f64()?,
            xy: r.f64()?,
            yy: r.f64()?,
        })
    }
}

/// A list: its length, then its items.
impl<T: Record> Record for Vec<T> {
    const MIN: usize = 8;
    fn put(&self, w: &mut Writer) {
        w.u64(self.len() as u64);
        self.iter().for_each(|x| x.put(w));
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        let k = r.count(T::MIN.max(1))?;
        (0..k).map(|_| T::get(r)).collect()
    }
}

/// 0 for none, 1 and the value for some.
impl<T: Record> Record for Option<T> {
    const MIN: usize = 8;
    fn put(&self, w: &mut Writer) {
        match self {
            Some(x) => {
                w.u64(1);
                x.put(w);
            }
            None => w.u64(0),
        }
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        Ok(match r.u64()? {
            0 => None,
            _ => Some(T::get(r)?),
        })
    }
}

impl<A: Record, B: Record> Record for (A, B) {
    const MIN: usize = A::MIN + B::MIN;
    fn put(&self, w: &mut Writer) {
        self.0.put(w);
        self.1.put(w);
    }
    fn get(r: &mut Reader) -> Result<Self, String> {
        Ok((A::get(r)?, B::get(r)?))
    }
}

/// A struct whose fields are records, written in the order listed; the
/// fields not listed (after `..`) are not saved and start from the given
/// values when read.
macro_rules! record {
    ($t:ident { $($f:ident),* $(,)? } $(.. $rest:expr)?) => {
        impl Record for $t {
            const MIN: usize = 1;
            fn put(&self, w: &mut Writer) {
                $( self.$f.put(w); )*
            }
            fn get(r: &mut Reader) -> Result<Self, String> {
                Ok($t { $( $f: Record::get(r)?, )* $(.. $rest)? })
            }
        }
    };
}
pub(super) use record;
