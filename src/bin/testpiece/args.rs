//! A small argument reader: `--flag`, `--key value`, `--key=value`, positionals.

use std::collections::BTreeMap;

#[derive(Debug, Default)]
pub struct Args {
    pub positional: Vec<String>,
    /// Every occurrence of each option, in order.
    options: BTreeMap<String, Vec<Option<String>>>,
    used: std::cell::RefCell<Vec<String>>,
}

impl Args {
    /// `takes_value` names the options that take a value (without `--`).
    pub fn parse(raw: &[String], takes_value: &[&str]) -> Result<Self, String> {
        let mut a = Args::default();
        let mut it = raw.iter();
        while let Some(s) = it.next() {
            if let Some(name) = s.strip_prefix("--") {
                let (k, v) = match name.split_once('=') {
                    Some((k, v)) => (k.to_string(), Some(v.to_string())),
                    None if takes_value.contains(&name) => {
                        let v = it
                            .next()
                            .ok_or_else(|| format!("option --{name} needs a value"))?;
                        (name.to_string(), Some(v.clone()))
                    }
                    None => (name.to_string(), None),
                };
                a.options.entry(k).or_default().push(v);
            } else {
                a.positional.push(s.clone());
            }
        }
        Ok(a)
    }

    pub fn flag(&self, name: &str) -> bool {
        self.used.borrow_mut().push(name.to_string());
        self.options.contains_key(name)
    }

    #[allow(dead_code)] // used by commands with options
    pub fn value(&self, name: &str) -> Option<&str> {
        self.used.borrow_mut().push(name.to_string());
        self.options
            .get(name)
            .and_then(|v| v.last())
            .and_then(|v| v.as_deref())
    }

    /// Every value of an option given several times (`--repeat A --repeat B`), in order.
    #[allow(dead_code)] // used by commands with repeatable options
    pub fn values(&self, name: &str) -> Vec<&str> {
        self.used.borrow_mut().push(name.to_string());
        self.options
            .get(name)
            .map(|v| v.iter().filter_map(|x| x.as_deref()).collect())
            .unwrap_or_default()
    }

    /// An error naming the first option the command did not ask about.
    pub fn reject_unknown(&self, command: &str) -> Result<(), String> {
        let used = self.used.borrow();
        match self.options.keys().find(|k| !used.contains(k)) {
            Some(k) => Err(format!(
                "unknown option --{k} for `testpiece {command}` (see `testpiece {command} --help`)"
            )),
            None => Ok(()),
        }
    }
}
