//! The old spellings of flags that became one flag with values (`--no-ssr` is `--ssr off`,
//! `--dof` is `--dof on`). They are hidden: [`rewrite`] turns them into the new spelling
//! before the command line is parsed and says so on stderr, for one release.

use std::ffi::OsString;

/// An old spelling and the arguments it stands for.
struct Old {
    /// The old flag.
    flag: &'static str,
    /// What it becomes.
    new: &'static [&'static str],
}

/// Flags whose old form was a `--no-` pair or a bare switch.
const OLD: &[Old] = &[
    Old {
        flag: "--no-shadows",
        new: &["--shadows", "off"],
    },
    Old {
        flag: "--no-energy-compensation",
        new: &["--energy-compensation", "off"],
    },
    Old {
        flag: "--no-light-culling",
        new: &["--light-culling", "off"],
    },
    Old {
        flag: "--no-shadow-cache",
        new: &["--shadow-cache", "off"],
    },
    Old {
        flag: "--no-ao-denoise",
        new: &["--ao-denoise", "off"],
    },
    Old {
        flag: "--no-ao-multi-bounce",
        new: &["--ao-multi-bounce", "off"],
    },
    Old {
        flag: "--no-ssr",
        new: &["--ssr", "off"],
    },
    Old {
        flag: "--no-auto-probes",
        new: &["--gi-auto", "off", "--reflection-probes-auto", "off"],
    },
    Old {
        flag: "--no-specular-aa",
        new: &["--specular-aa", "off"],
    },
    Old {
        flag: "--no-dof",
        new: &["--dof", "off"],
    },
    Old {
        flag: "--no-gltf-light-shadows",
        new: &["--gltf-light-shadows", "off"],
    },
];

/// Switches that took no value and now take `on` or `off`: bare, they mean `on`.
const BARE: &[&str] = &["--specular-aa", "--dof"];

/// `args` with every old spelling replaced, and one note per old flag used.
pub fn rewrite(args: impl IntoIterator<Item = OsString>) -> (Vec<OsString>, Vec<String>) {
    let args: Vec<OsString> = args.into_iter().collect();
    let mut out = Vec::with_capacity(args.len());
    let mut notes: Vec<String> = Vec::new();
    let mut note = |old: &str, new: &str| {
        let line = format!(
            "note: {old} is now written {new}; the old spelling is accepted until the next release"
        );
        if !notes.contains(&line) {
            notes.push(line);
        }
    };
    let mut i = 0;
    while i < args.len() {
        let arg = &args[i];
        i += 1;
        let Some(text) = arg.to_str() else {
            out.push(arg.clone());
            continue;
        };
        if text == "--" {
            out.extend(args[i - 1..].iter().cloned());
            break;
        }
        if let Some(old) = OLD.iter().find(|o| o.flag == text) {
            note(old.flag, &old.new.join(" "));
            out.extend(old.new.iter().map(OsString::from));
            continue;
        }
        if BARE.contains(&text) {
            let valued = args
                .get(i)
                .and_then(|next| next.to_str())
                .is_some_and(|next| ["on", "off"].contains(&next.to_ascii_lowercase().as_str()));
            if !valued {
                note(text, &format!("{text} on"));
                out.push(arg.clone());
                out.push("on".into());
                continue;
            }
        }
        out.push(arg.clone());
    }
    (out, notes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(args: &[&str]) -> (Vec<String>, Vec<String>) {
        let (out, notes) = rewrite(args.iter().map(OsString::from));
        (
            out.into_iter()
                .map(|a| a.to_string_lossy().into_owned())
                .collect(),
            notes,
        )
    }

    #[test]
    fn old_pairs_become_one_flag_with_a_note_each() {
        let (args, notes) = run(&[
            "lumen",
            "render",
            "--no-ssr",
            "--no-auto-probes",
            "--no-ssr",
        ]);
        assert_eq!(
            args,
            [
                "lumen",
                "render",
                "--ssr",
                "off",
                "--gi-auto",
                "off",
                "--reflection-probes-auto",
                "off",
                "--ssr",
                "off"
            ]
        );
        assert_eq!(notes.len(), 2, "{notes:?}");
        assert!(
            notes[0].contains("--no-ssr is now written --ssr off"),
            "{notes:?}"
        );
    }

    #[test]
    fn a_bare_switch_means_on_and_a_valued_one_is_left_alone() {
        let (args, notes) = run(&["lumen", "render", "--dof", "--specular-aa", "off", "--dof"]);
        assert_eq!(
            args,
            [
                "lumen",
                "render",
                "--dof",
                "on",
                "--specular-aa",
                "off",
                "--dof",
                "on"
            ]
        );
        assert_eq!(notes.len(), 1);
        let (args, notes) = run(&["lumen", "render", "--dof", "scene.glb"]);
        assert_eq!(args, ["lumen", "render", "--dof", "on", "scene.glb"]);
        assert_eq!(notes.len(), 1);
    }

    #[test]
    fn nothing_after_a_double_dash_is_rewritten() {
        let (args, notes) = run(&["lumen", "render", "--", "--no-ssr"]);
        assert_eq!(args, ["lumen", "render", "--", "--no-ssr"]);
        assert!(notes.is_empty());
    }
}
