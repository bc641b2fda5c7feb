//! `raycast completions bash|zsh|fish|powershell`: shell completion scripts made from the option table, so
//! that they offer exactly the options the parser takes.

use crate::job::OPTIONS;

/// The completion script for `shell`, or `None` for a shell raycast does not know.
pub fn script(shell: &str) -> Option<String> {
    match shell {
        "bash" => Some(bash()),
        "zsh" => Some(zsh()),
        "fish" => Some(fish()),
        "powershell" => Some(powershell()),
        _ => None,
    }
}

/// The shells `script` knows, as `completions` offers them.
const SHELLS: &str = "bash zsh fish powershell";

/// What to complete after an option: files, or nothing (a number or a word the user types).
fn takes_file(values: &str) -> bool {
    values.contains("FILE")
}

fn bash() -> String {
    let names: Vec<String> = OPTIONS.iter().map(|o| format!("-{}", o.name)).collect();
    let file_options: Vec<String> = OPTIONS
        .iter()
        .filter(|o| o.values == "FILE")
        .map(|o| format!("-{}", o.name))
        .collect();
    format!(
        r#"# bash completion for raycast: source it, or put it in ~/.local/share/bash-completion/completions/raycast
_raycast() {{
    local current="${{COMP_WORDS[COMP_CWORD]}}"
    local previous="${{COMP_WORDS[COMP_CWORD-1]}}"
    if [[ $COMP_CWORD -eq 1 && "completions" == "$current"* ]]; then
        COMPREPLY=($(compgen -W "completions {names}" -- "$current"))
        return
    fi
    if [[ "${{COMP_WORDS[1]}}" == completions ]]; then
        COMPREPLY=($(compgen -W "{shells}" -- "$current"))
        return
    fi
    case "$previous" in
        {files})
            COMPREPLY=($(compgen -f -- "$current"))
            return
            ;;
        -format)
            COMPREPLY=($(compgen -W "png ppm tga" -- "$current"))
            return
            ;;
    esac
    if [[ "$current" == -* ]]; then
        COMPREPLY=($(compgen -W "{names}" -- "$current"))
    else
        COMPREPLY=($(compgen -f -- "$current"))
    fi
}}
complete -o filenames -F _raycast raycast
"#,
        names = names.join(" "),
        files = file_options.join("|"),
        shells = SHELLS,
    )
}

fn zsh() -> String {
    let mut specs = String::new();
    for option in OPTIONS {
        let help = option
            .help
            .replace('\'', "'\\''")
            .replace('[', "(")
            .replace(']', ")");
        let action = if option.name == "format" {
            ":format:(png ppm tga)".to_string()
        } else if takes_file(option.values) {
            ":file:_files".to_string()
        } else if option.values.is_empty() {
            String::new()
        } else {
            format!(":{}: ", option.values.to_lowercase())
        };
        specs.push_str(&format!("    '-{}[{help}]{action}' \\\n", option.name));
    }
    format!(
        "#compdef raycast
# zsh completion for raycast: put it on your $fpath as _raycast
_arguments -s \\
{specs}    '*:file:_files'
"
    )
}

fn fish() -> String {
    let mut text = format!(
        "# fish completion for raycast: put it in ~/.config/fish/completions/raycast.fish\n\
         complete -c raycast -n '__fish_use_subcommand' -a completions -d 'print a shell completion script'\n\
         complete -c raycast -n '__fish_seen_subcommand_from completions' -a '{SHELLS}'\n",
    );
    for option in OPTIONS {
        let help = option.help.replace('\'', "\\'");
        let takes = if option.name == "format" {
            " -x -a 'png ppm tga'".to_string()
        } else if takes_file(option.values) {
            " -r -F".to_string()
        } else if option.values.is_empty() {
            String::new()
        } else {
            " -x".to_string()
        };
        text.push_str(&format!(
            "complete -c raycast -o {}{takes} -d '{help}'\n",
            option.name
        ));
    }
    text
}

/// PowerShell (Windows' shell, and on every system): a native completer. Where it offers
/// nothing (after an option that takes a file), PowerShell completes paths itself.
fn powershell() -> String {
    let mut options = String::new();
    for option in OPTIONS {
        let help = option.help.replace('\'', "''");
        options.push_str(&format!("        @('-{}', '{help}'),\n", option.name));
    }
    let shells: Vec<String> = SHELLS.split(' ').map(|s| format!("'{s}'")).collect();
    format!(
        r#"# PowerShell completion for raycast: add it to your profile (notepad $PROFILE)
Register-ArgumentCompleter -Native -CommandName raycast, raycast.exe -ScriptBlock {{
    param($wordToComplete, $commandAst, $cursorPosition)
    $words = @($commandAst.CommandElements | ForEach-Object {{ $_.ToString() }})
    $previous = if ($wordToComplete -eq '') {{ $words[-1] }} else {{ $words[-2] }}
    if ($words.Count -ge 2 -and $words[1] -eq 'completions') {{
        $choices = @({shells})
    }} elseif ($previous -eq '-format') {{
        $choices = @('png', 'ppm', 'tga')
    }} elseif ($wordToComplete -like '-*' -or $words.Count -eq 1) {{
        $options = @(
{options}        @('completions', 'print a shell completion script')
        )
        $options | Where-Object {{ $_[0] -like "$wordToComplete*" }} | ForEach-Object {{
            [System.Management.Automation.CompletionResult]::new($_[0], $_[0], 'ParameterName', $_[1])
        }}
        return
    }} else {{
        return
    }}
    $choices | Where-Object {{ $_ -like "$wordToComplete*" }} | ForEach-Object {{
        [System.Management.Automation.CompletionResult]::new($_, $_, 'ParameterValue', $_)
    }}
}}
"#,
        shells = shells.join(", "),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_option_is_offered_by_every_shell() {
        for shell in SHELLS.split(' ') {
            let text = script(shell).unwrap();
            for option in OPTIONS {
                let offered = match shell {
                    "fish" => format!("-o {}", option.name),
                    "powershell" => format!("@('-{}', '", option.name),
                    _ => format!("-{}", option.name),
                };
                assert!(text.contains(&offered), "{shell} lacks -{}", option.name);
            }
        }
        assert_eq!(script("cmd"), None);
    }
}
