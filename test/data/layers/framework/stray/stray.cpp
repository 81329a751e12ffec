int stray = 0;
