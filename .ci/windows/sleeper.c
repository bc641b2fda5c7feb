/* A renderer that never finishes, for the Windows cage's test under Wine (.ci/windows/run): it
 * starts a copy of itself that would outlive it, then both sleep. The line's job object must
 * end both at the line's --timeout. */
#include <windows.h>
#include <string.h>

int main(int argc, char **argv)
{
    if (argc < 2 || strcmp(argv[1], "child") != 0) {
        char self[MAX_PATH];
        char command[MAX_PATH + 16];
        STARTUPINFOA startup = { sizeof startup };
        PROCESS_INFORMATION process;
        GetModuleFileNameA(NULL, self, MAX_PATH);
        wsprintfA(command, "\"%s\" child", self);
        CreateProcessA(NULL, command, NULL, NULL, FALSE, 0, NULL, NULL, &startup, &process);
    }
    Sleep(INFINITE);
    return 0;
}
