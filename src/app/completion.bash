# bash completion for inkline (installed as share/bash-completion/completions/inkline). The flags
# and their fixed values come from `inkline COMMAND --help` as you type, so they never drift.
_inkline() {
    local cur=${COMP_WORDS[COMP_CWORD]} cmd=${COMP_WORDS[1]}
    if ((COMP_CWORD == 1)); then
        COMPREPLY=($(compgen -W "render view bench help --help --version" -- "$cur"))
        return
    fi
    if [[ $cmd == help ]]; then
        ((COMP_CWORD == 2)) && COMPREPLY=($(compgen -W "render view bench" -- "$cur"))
        return
    fi
    local help
    help=$("${COMP_WORDS[0]}" "$cmd" --help 2>/dev/null) || return
    # bash splits "--flag=value" at '=' (COMP_WORDBREAKS): "--flag" "=" "value".
    local flag=""
    if [[ $cur == = ]]; then
        flag=${COMP_WORDS[COMP_CWORD - 1]}; cur=""
    elif [[ ${COMP_WORDS[COMP_CWORD - 1]} == = ]]; then
        flag=${COMP_WORDS[COMP_CWORD - 2]}
    fi
    if [[ -n $flag ]]; then
        # A value of fixed choices ("--format=svg|pdf|png|json") completes to them, any other to files.
        local values
        values=$(sed -n "s/^  ${flag}=\([a-z0-9-]*|[a-z0-9|-]*\).*/\1/p" <<<"$help" | tr '|' ' ')
        if [[ $flag == --style ]]; then
            # The presets installed beside the program ($INKLINE_STYLES first, as inkline looks).
            local dir=${INKLINE_STYLES:-$(dirname "$(readlink -f "$(command -v "${COMP_WORDS[0]}")")")/../share/inkline/styles} f
            for f in "$dir"/*.json; do [[ -e $f ]] && values+=" $(basename "$f" .json)"; done
            compopt -o filenames 2>/dev/null  # and style files
            COMPREPLY=($(compgen -W "$values" -- "$cur") $(compgen -f -- "$cur"))
            return
        fi
        if [[ -n $values ]]; then
            COMPREPLY=($(compgen -W "$values" -- "$cur"))
        else
            compopt -o filenames 2>/dev/null
            COMPREPLY=($(compgen -f -- "$cur"))
        fi
        return
    fi
    if [[ $cur == -* ]]; then
        local flags
        flags=$(grep -o -- '^  \(-o [A-Z]*, \)\?--[a-z0-9-]*=\?' <<<"$help" | sed 's/^ *\(-o [A-Z]*, \)\?//')
        compopt -o nospace 2>/dev/null
        COMPREPLY=($(compgen -W "$flags --help" -- "$cur"))
        # A switch is complete as typed: add the space that nospace withheld.
        ((${#COMPREPLY[@]} == 1)) && [[ ${COMPREPLY[0]} != *= ]] && COMPREPLY[0]+=" "
        return
    fi
    compopt -o filenames 2>/dev/null
    COMPREPLY=($(compgen -f -- "$cur"))
}
complete -F _inkline inkline
