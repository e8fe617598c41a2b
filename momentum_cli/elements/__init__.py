"""Elements: contact laws and joints that write their own equations (see base.py).

`contacts` holds the contact laws (restitution and tangential), `joints` the joint
kinds; `keys` the structured identities of unknowns and `kinds` the enums.
"""
