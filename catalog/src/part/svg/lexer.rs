//! The number micro-syntax of SVG attributes (`d`, `points`,
//! `transform`, `viewBox`), shared by their parsers.

/// Numbers of SVG attribute micro-syntax: separators are whitespace and
/// commas, a sign or a second '.' starts a new number, arc flags may be
/// written without separators.
pub(super) struct Lexer<'a> {
    s: &'a [u8],
    i: usize,
}

impl<'a> Lexer<'a> {
    pub(super) fn new(text: &'a str) -> Self {
        Lexer {
            s: text.as_bytes(),
            i: 0,
        }
    }

    /// Consumes the character [`Lexer::peek`] returned (a command letter).
    pub(super) fn bump(&mut self) {
        self.i += 1;
    }

    /// Up to 20 bytes from the current position, to show where parsing
    /// stopped.
    pub(super) fn tail(&self) -> String {
        let s = &self.s[self.i.min(self.s.len())..];
        String::from_utf8_lossy(&s[..s.len().min(20)]).into_owned()
    }

    fn skip_sep(&mut self) {
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_whitespace() || self.s[self.i] == b',')
        {
            self.i += 1;
        }
    }

    pub(super) fn at_end(&mut self) -> bool {
        self.skip_sep();
        self.i >= self.s.len()
    }

    pub(super) fn peek(&mut self) -> Option<u8> {
        self.skip_sep();
        self.s.get(self.i).copied()
    }

    pub(super) fn starts_number(&mut self) -> bool {
        matches!(self.peek(), Some(c) if c.is_ascii_digit() || c == b'-' || c == b'+' || c == b'.')
    }

    pub(super) fn number(&mut self) -> Option<f64> {
        self.skip_sep();
        let start = self.i;
        let s = self.s;
        let mut j = self.i;
        if j < s.len() && (s[j] == b'-' || s[j] == b'+') {
            j += 1;
        }
        let mut digits = false;
        while j < s.len() && s[j].is_ascii_digit() {
            j += 1;
            digits = true;
        }
        if j < s.len() && s[j] == b'.' {
            j += 1;
            while j < s.len() && s[j].is_ascii_digit() {
                j += 1;
                digits = true;
            }
        }
        if !digits {
            return None;
        }
        if j < s.len() && (s[j] == b'e' || s[j] == b'E') {
            let mut k = j + 1;
            if k < s.len() && (s[k] == b'-' || s[k] == b'+') {
                k += 1;
            }
            if k < s.len() && s[k].is_ascii_digit() {
                while k < s.len() && s[k].is_ascii_digit() {
                    k += 1;
                }
                j = k;
            }
        }
        let text = std::str::from_utf8(&s[start..j]).ok()?;
        let v = text.parse::<f64>().ok()?;
        self.i = j;
        Some(v)
    }

    pub(super) fn flag(&mut self) -> Option<bool> {
        match self.peek()? {
            b'0' => {
                self.i += 1;
                Some(false)
            }
            b'1' => {
                self.i += 1;
                Some(true)
            }
            _ => None,
        }
    }
}
