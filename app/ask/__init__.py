"""Ask the class: questions, rounds of answers, and the judges of state answers (`judges`)."""
