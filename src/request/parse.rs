//! Parsers for comma-separated values (`LO,HI`, `X,Y,Z`, `I,J`, `R,G,B`): the command line's
//! flags and the text forms a request's fields take.

fn list<T: std::str::FromStr, const N: usize>(s: &str, what: &str) -> Result<[T; N], String> {
    let values: Vec<T> = s
        .split(',')
        .map(|t| t.trim().parse::<T>().map_err(|_| format!("`{}` is not {what}", t.trim())))
        .collect::<Result<_, _>>()?;
    values.try_into().map_err(|_| format!("expected {N} comma-separated values"))
}

/// `A,B,...`: N numbers.
pub fn numbers<const N: usize>(s: &str) -> Result<[f64; N], String> {
    list::<f64, N>(s, "a number")
}

/// `X,Y,Z`.
pub fn vector(s: &str) -> Result<[f64; 3], String> {
    numbers::<3>(s)
}

/// `A,B,C,D`.
pub fn four(s: &str) -> Result<[f64; 4], String> {
    numbers::<4>(s)
}

/// `LO,HI` with LO < HI.
pub fn range(s: &str) -> Result<(f64, f64), String> {
    let [lo, hi] = numbers::<2>(s)?;
    if hi > lo { Ok((lo, hi)) } else { Err("the range needs LO < HI".into()) }
}

/// `I,J`: two non-negative integers.
pub fn index_pair(s: &str) -> Result<(u64, u64), String> {
    let [i, j] = list::<u64, 2>(s, "a non-negative integer")?;
    Ok((i, j))
}

/// `R,G,B`: three 0–255 values.
pub fn rgb(s: &str) -> Result<[u8; 3], String> {
    list::<u8, 3>(s, "a value from 0 to 255")
}

/// `SEA;LOW;MID;HIGH;PEAK`, each `R,G,B`.
pub fn palette(s: &str) -> Result<crate::terrain::Palette, String> {
    let colours: Vec<[u8; 3]> = s.split(';').map(rgb).collect::<Result<_, _>>()?;
    let [sea, low, mid, high, peak]: [[u8; 3]; 5] =
        colours.try_into().map_err(|_| "expected five colours SEA;LOW;MID;HIGH;PEAK, each R,G,B".to_string())?;
    Ok(crate::terrain::Palette { sea, low, mid, high, peak })
}

/// `W,H`: a picture size in pixels.
pub fn size(s: &str) -> Result<(usize, usize), String> {
    let [w, h] = list::<usize, 2>(s, "a pixel count")?;
    Ok((w, h))
}
