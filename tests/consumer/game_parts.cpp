// The game's own code in targets named fx, terrain and campfire: cellfx's targets are prefixed,
// so these do not clash with them.
int game_part() { return 42; }
#ifdef GAME_PARTS_MAIN
int main() { return game_part() == 42 ? 0 : 1; }
#endif
