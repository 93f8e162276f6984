// io/text_escape.h: user text (names, paths, descriptions, keys, tokens of an input) made safe for
// the places it reaches: a message on the terminal, a comment or a string in a written file.
//
// Input text is bytes: a file name or a --name need not be UTF-8, and a file may hold control bytes.
// Printed raw, ESC and BEL drive the terminal and NUL ends a C string; inside a written file a line
// break ends a comment (the rest of the "comment" becomes code) and an invalid byte makes the file
// unreadable (Python refuses the script, XML and JSON readers refuse the document). So text from
// inputs is escaped before it goes anywhere:
//  - control characters (C0, DEL, the C1 controls U+0080 to U+009F) as \n, \t, \r or \u00XX;
//  - the Unicode line and paragraph separators U+2028, U+2029 (line breaks to some readers:
//    ECMAScript, Unicode's own line-breaking rules) as \u2028, \u2029;
//  - the noncharacters U+FFFE, U+FFFF (not characters at all to XML 1.0, Sec. 2.2, which refuses a
//    document holding them) as \ufffe, \uffff;
//  - bytes that are not part of a well-formed UTF-8 sequence (the Unicode Standard 15.0, Table 3-7:
//    no overlong forms, no surrogates, nothing above U+10FFFF) as \xNN.
// Every other character, ASCII or not, stays as it is: the result is well-formed UTF-8.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace aniso {

// One line: every line break escaped too (\n, \r). For messages that quote user text and for the
// comments and strings of written files.
std::string text_escape(std::string_view s);

// For the terminal, text of several lines (an error message, a file's description): as
// text_escape, but '\n' and '\t' stay.
std::string terminal_text(std::string_view s);

// The byte offset of the first byte that is not part of a well-formed UTF-8 sequence, or nullopt
// when the whole text is UTF-8.
std::optional<size_t> first_invalid_utf8(std::string_view s);

}  // namespace aniso
