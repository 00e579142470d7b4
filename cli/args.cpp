#include <cstdlib>

#include "cli/commands.h"

namespace vfsd::cli {

Args::Args(const char*, int argc, char** argv) {
    for (int i = 0; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--help" || a == "-h") {
            help_ = true;
        } else if (a.rfind("--", 0) == 0 && a.size() > 2) {
            const auto eq = a.find('=');
            if (eq != std::string::npos) {
                options_[a.substr(2, eq - 2)] = a.substr(eq + 1);
            } else if (i + 1 < argc && std::string(argv[i + 1]).rfind("--", 0) != 0) {
                options_[a.substr(2)] = argv[++i];
            } else {
                options_[a.substr(2)] = "";  // a flag
            }
        } else {
            positional_.push_back(a);
        }
    }
}

const std::string& Args::positional(std::size_t i, const char* what) const {
    if (i >= positional_.size()) throw UsageError(std::string("missing ") + what);
    return positional_[i];
}

std::string Args::get(const std::string& option, const std::string& fallback) const {
    auto it = options_.find(option);
    return it == options_.end() ? fallback : it->second;
}

double Args::get_number(const std::string& option, double fallback) const {
    auto it = options_.find(option);
    if (it == options_.end()) return fallback;
    char* end = nullptr;
    const double value = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || *end != '\0') throw UsageError("--" + option + " expects a number, got '" + it->second + "'");
    return value;
}

void Args::expect(const std::vector<std::string>& known, std::size_t min_positional, std::size_t max_positional) const {
    for (const auto& [name, value] : options_) {
        bool ok = false;
        for (const auto& k : known) ok = ok || k == name;
        if (!ok) throw UsageError("unknown option --" + name);
    }
    if (positional_.size() < min_positional) throw UsageError("too few arguments");
    if (positional_.size() > max_positional) throw UsageError("unexpected argument '" + positional_[max_positional] + "'");
}

}  // namespace vfsd::cli
