// The style sheet and the script of the HTML report page (html_assets.cpp). The script reads
// the page's LAYERS and META constants, written before it by HtmlReportWriter::finish().
#pragma once

namespace carve::html {

extern const char* const kCss;
extern const char* const kScript;

}  // namespace carve::html
