#pragma once

#include <string>
#include <vector>

namespace orbis::cli {

int renderCommand(const std::vector<std::string>& args);
int benchCommand(const std::vector<std::string>& args);
int infoCommand(const std::vector<std::string>& args);
int viewCommand(const std::vector<std::string>& args);
int measureCommand(const std::vector<std::string>& args);
int viewshedCommand(const std::vector<std::string>& args);
int wpsCommand(const std::vector<std::string>& args);
int convertCommand(const std::vector<std::string>& args);

}  // namespace orbis::cli
