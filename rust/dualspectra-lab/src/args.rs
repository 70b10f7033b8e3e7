//! Command-line flags of the research harnesses (`--name` and `--name VALUE`, anywhere
//! among the positional arguments), so that no setting hides in an environment variable.

/// The program's arguments after its name.
pub fn from_env() -> Vec<String> {
    std::env::args().skip(1).collect()
}

/// Remove `--name` from `args`; whether it was there.
pub fn take_flag(args: &mut Vec<String>, name: &str) -> bool {
    let before = args.len();
    args.retain(|a| a != name);
    args.len() != before
}

/// Remove `--name VALUE` (or `--name=VALUE`) from `args` and parse VALUE; `Ok(None)` when
/// absent, an error when the value is missing or does not parse.
pub fn take_value<T: std::str::FromStr>(args: &mut Vec<String>, name: &str) -> Result<Option<T>, String> {
    let prefix = format!("{name}=");
    let Some(i) = args.iter().position(|a| a == name || a.starts_with(&prefix)) else {
        return Ok(None);
    };
    let arg = args.remove(i);
    let text = match arg.strip_prefix(&prefix) {
        Some(v) => v.to_string(),
        None if i < args.len() => args.remove(i),
        None => return Err(format!("{name} needs a value")),
    };
    text.parse().map(Some).map_err(|_| format!("{name}: cannot read '{text}'"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_and_values_are_taken_out_of_the_positionals() {
        let mut a: Vec<String> = ["data", "--gt-start", "4", "--res", "0", "--si=local"].map(String::from).to_vec();
        assert!(take_flag(&mut a, "--gt-start"));
        assert!(!take_flag(&mut a, "--gt-start"));
        assert_eq!(take_value::<usize>(&mut a, "--res"), Ok(Some(0)));
        assert_eq!(take_value::<String>(&mut a, "--si"), Ok(Some("local".into())));
        assert_eq!(take_value::<usize>(&mut a, "--threads"), Ok(None));
        assert_eq!(a, ["data", "4"]);
        let mut bad: Vec<String> = ["--res", "x"].map(String::from).to_vec();
        assert!(take_value::<usize>(&mut bad, "--res").is_err());
        let mut missing: Vec<String> = vec!["--res".into()];
        assert!(take_value::<usize>(&mut missing, "--res").is_err());
    }
}
