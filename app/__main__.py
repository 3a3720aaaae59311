"""`python -m app [--host H] [--port P]`: start the lecture app (see `app.main`)."""

from app.main import main

if __name__ == "__main__":
    main()
