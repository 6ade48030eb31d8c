# An action's feedback topic carries `<pkg>/action/<Action>_FeedbackMessage` (with
# `<Action>_Feedback` inside). The rosidl parser that mcap-ros2-support vendors refuses a `_`
# in a type name (its rule for .msg file names); `parsable` gives the same definition with the
# underscores of those two names removed, so that it parses. Shared by the Python of
# msgs/tests/message_definitions.rs and tests/tests/recording.rs.
def parsable(name, text):
    if not name.endswith('_FeedbackMessage'):
        return name, text
    pkg, _, last = name.split('/')
    action = last[: -len('_FeedbackMessage')]
    return (pkg + '/msg/' + last.replace('_', ''),
            text.replace(action + '_Feedback', action + 'Feedback'))
