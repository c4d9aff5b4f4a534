/* format_bad.c - a fixture of source_format_control: not what .clang-format makes of it. */
int  add(int a,int b){return a+b;}
