//! Where in a scene file a TOML or serde error lies: the key at fault as a
//! dotted path (`bodies[1].spacing`) with its line and column, found by
//! reading the file's tables around the error's span (and, for an array
//! of tables, parsing its elements one by one as scenes).

use crate::error::SceneError;

impl SceneError {
    /// Turn a TOML/serde error into one line naming the key as a dotted path
    /// (`bodies[1].spacing`), its line and column.
    pub fn parse(origin: &str, text: &str, err: &toml::de::Error) -> Self {
        let mut message = err.message().trim().to_string();
        if message.is_empty() {
            // The TOML parser leaves some syntax errors unexplained (a key
            // with no value at the end of the file, stray bytes); the
            // position still says where.
            message =
                "invalid TOML syntax (a value, key, quote or bracket is missing or malformed)"
                    .to_string();
        }
        Self {
            file: origin.to_string(),
            key: err.span().map(|span| locate(text, span, &message)),
            message,
        }
    }
}

/// `path (line L, column C)` for a TOML/serde error. Serde's span is the value,
/// the key or the table at fault (for a probe, an internally tagged enum, the
/// whole `[[probes]]` array); the field the message names, the table headers
/// before the span and the key on its line complete the path.
fn locate(text: &str, span: std::ops::Range<usize>, message: &str) -> String {
    let mut start = span.start.min(text.len());
    let mut end = span.end.clamp(start, text.len());
    if let Some((s, e)) = element_at_fault(text, start, end, message) {
        (start, end) = (s, e);
    }
    let quoted = |prefix: &str| {
        let rest = message.strip_prefix(prefix)?.strip_prefix('`')?;
        rest.split('`').next().filter(|f| !f.is_empty())
    };
    let mut field = None;
    if let Some(f) = quoted("unknown field ") {
        start += find_key(&text[start..end], f).unwrap_or(0);
        field = Some(f);
    } else if let Some(f) = quoted("missing field ") {
        field = Some(f);
    } else if let Some(v) = quoted("unknown variant ") {
        start += find_value(&text[start..end], v).unwrap_or(0);
    }

    let before = &text[..start];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = text[line_start..start].chars().count() + 1;
    let line_text = text[line_start..].lines().next().unwrap_or("");

    // The table: the last header up to and including this line.
    let mut table = None;
    let mut counts: std::collections::HashMap<String, usize> = Default::default();
    for l in text[..line_start].lines().chain([line_text]) {
        match header(l) {
            Some((name, true)) => {
                let n = counts.entry(name.clone()).or_default();
                *n += 1;
                table = Some(format!("{name}[{}]", *n - 1));
            }
            Some((name, false)) => {
                // `[bodies.shape]` after `[[bodies]]` belongs to the last body.
                let (first, rest) = name.split_once('.').unwrap_or((&name, ""));
                table = Some(match counts.get(first) {
                    Some(n) if !rest.is_empty() => format!("{first}[{}].{rest}", n - 1),
                    _ => name.clone(),
                });
            }
            None => {}
        }
    }
    // The key on this line when the span starts in its value, and the key
    // within an inline table (`eos = { kind = ...`).
    let mut path: Vec<String> = table.into_iter().collect();
    let upto = &text[line_start..start];
    if header(line_text).is_none() && !line_text.trim_start().starts_with('#') {
        if let Some((k, value)) = upto.split_once('=') {
            path.push(unquote(k));
            if let Some(i) = value.rfind(['{', ',']) {
                if let Some((inner, _)) = value[i + 1..].split_once('=') {
                    path.push(unquote(inner));
                }
            }
        }
    }
    if let Some(f) = field {
        if path.last().map(String::as_str) != Some(f) {
            path.push(f.to_string());
        }
    }
    let path: Vec<String> = path.into_iter().filter(|p| !p.is_empty()).collect();
    if path.is_empty() {
        format!("line {line}, column {column}")
    } else {
        format!("{} (line {line}, column {column})", path.join("."))
    }
}

fn unquote(key: &str) -> String {
    key.trim().trim_matches(['"', '\'']).to_string()
}

/// A table header line: its name, and whether it is an array of tables.
fn header(line: &str) -> Option<(String, bool)> {
    let l = line.trim_start();
    let (inner, array) = match l.strip_prefix("[[") {
        Some(rest) => (rest, true),
        None => (l.strip_prefix('[')?, false),
    };
    let name = inner.split(']').next()?.trim();
    (!name.is_empty() && !name.contains(['=', '"', '\''])).then(|| (name.to_string(), array))
}

/// `key =` at the start of a line or after `{` or `,` in `region`.
fn find_key(region: &str, key: &str) -> Option<usize> {
    region.match_indices(key).map(|(i, _)| i).find(|&i| {
        let lead = region[..i].trim_end_matches([' ', '\t']);
        let tail = region[i + key.len()..].trim_start_matches([' ', '\t']);
        (lead.is_empty() || lead.ends_with(['\n', '{', ','])) && tail.starts_with('=')
    })
}

/// `= "value"` (or `'value'`) in `region`: the position of the quoted value.
fn find_value(region: &str, value: &str) -> Option<usize> {
    [format!("\"{value}\""), format!("'{value}'")]
        .iter()
        .flat_map(|q| region.match_indices(q.as_str()).map(|(i, _)| i))
        .filter(|&i| region[..i].trim_end_matches([' ', '\t']).ends_with('='))
        .min()
}

/// When a span covers several elements of an array of tables (serde reports
/// an internally tagged enum's errors on the whole array), the element at
/// fault: the first that, parsed on its own, gives the same message.
fn element_at_fault(text: &str, start: usize, end: usize, message: &str) -> Option<(usize, usize)> {
    let region = &text[start..end];
    let (name, true) = header(region.lines().next()?)? else {
        return None;
    };
    let mut starts = Vec::new();
    let mut offset = start;
    for l in region.split_inclusive('\n') {
        if header(l) == Some((name.clone(), true)) {
            starts.push(offset);
        }
        offset += l.len();
    }
    if starts.len() < 2 {
        return None;
    }
    starts.push(end);
    starts.windows(2).map(|w| (w[0], w[1])).find(|&(s, e)| {
        matches!(toml::from_str::<super::Scene>(&text[s..e]),
            Err(err) if err.message().trim() == message)
    })
}
